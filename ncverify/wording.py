"""The words a control uses for things core rules talk about (how a modal cycle is
cancelled, which alarm a missing feed raises), from ``dialects/<dialect>/wording.toml``.

Core rules run on every dialect; a message that names G80 or an E60 alarm number would be
wrong on a SINUMERIK or Klartext program. Rules ask for a word and leave it out of the
message when the dialect has none.
"""
from __future__ import annotations

from functools import cache

from .resources import data_dir, read_table


@cache
def wording(dialect: str, profile: str | None = None) -> dict[str, str]:
    path = data_dir("dialects") / dialect / "wording.toml"
    if not path.is_file():
        return {}
    table = read_table(path)
    words = {key: value for key, value in table.items() if isinstance(value, str)}
    words.update(table.get("profile", {}).get(profile or "", {}))
    return words
