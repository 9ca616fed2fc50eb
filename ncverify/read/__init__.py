"""Stage 1, read: program text to per-dialect block syntax. One module per dialect family."""
