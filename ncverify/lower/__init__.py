"""Stage 2, lower: per-dialect block syntax to the dialect-neutral IR (:mod:`ncverify.ir`)."""
