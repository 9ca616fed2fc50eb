"""The parsed-table cache (``ncverify.resources.parse_table``): it answers exactly what
``tomllib`` answers for the shipped tables, and an entry that is missing, broken, of other
text or not writable falls back to parsing."""
from __future__ import annotations

import json
import tomllib

import pytest

from ncverify import resources
from ncverify.resources import data_dir, parse_table, read_table


@pytest.fixture
def folder(tmp_path, monkeypatch):
    target = tmp_path / "tables"
    monkeypatch.setattr(resources, "parsed_tables_folder", lambda: target)
    return target


def _shipped_texts() -> list[str]:
    tables = [path.read_bytes().decode() for path in sorted(data_dir("dialects").rglob("*.toml"))]
    fronts = [path.read_text(encoding="utf-8").split("+++", 2)[1] for path in sorted(data_dir("rules").glob("*/*.md"))]
    return tables + fronts


def test_every_shipped_table_reads_back_as_tomllib_parses_it_in_the_same_order(folder):
    texts = _shipped_texts()
    assert len(texts) > 200
    for text in texts:
        expected = repr(tomllib.loads(text))  # repr: the key order and the int/float types count too
        assert repr(parse_table(text)) == expected  # parsed, stored
        assert repr(parse_table(text)) == expected  # read back
    assert len(list(folder.glob("*.json"))) == len(set(texts))


def test_a_hit_is_read_from_the_entry_without_parsing(folder, monkeypatch):
    text = 'a = 1\nb = [1.5, "x", {c = true}]\n'
    parse_table(text)
    monkeypatch.setattr(tomllib, "loads", lambda _text: pytest.fail("parsed again although the entry is there"))
    assert parse_table(text) == {"a": 1, "b": [1.5, "x", {"c": True}]}


@pytest.mark.parametrize("damage", [b"", b"{", b"\xff\xfe", b"[1, 2]", b'{"key": "other", "table": {}}', b'{"table": {"a": 2}}'])
def test_a_broken_or_foreign_entry_is_parsed_again_and_rewritten(folder, damage):
    text = "a = 1\n"
    parse_table(text)
    [entry] = folder.glob("*.json")
    entry.write_bytes(damage)
    assert parse_table(text) == {"a": 1}
    assert json.loads(entry.read_text(encoding="utf-8"))["table"] == {"a": 1}


def test_an_entry_of_another_text_is_never_answered(folder):
    """Entries are named by the text's hash: the entry of one text copied over another's
    holds the other key and is ignored."""
    parse_table("a = 1\n")
    parse_table("a = 2\n")
    first, second = sorted(folder.glob("*.json"), key=lambda path: json.loads(path.read_text(encoding="utf-8"))["table"]["a"])
    second.write_bytes(first.read_bytes())
    assert parse_table("a = 2\n") == {"a": 2}


def test_a_folder_that_cannot_be_written_only_costs_the_parsing(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setattr(resources, "parsed_tables_folder", lambda: blocker / "tables")
    assert parse_table("a = 1\n") == {"a": 1}


def test_a_table_json_cannot_hold_is_not_kept(folder):
    assert parse_table("day = 2026-11-26\n") == tomllib.loads("day = 2026-11-26\n")
    assert not folder.exists() or not list(folder.glob("*.json"))


def test_errors_are_tomllib_s(folder):
    with pytest.raises(tomllib.TOMLDecodeError):
        parse_table("a = \n")
    assert not folder.exists() or not list(folder.glob("*.json"))


def test_a_file_is_read_as_tomllib_load_reads_it(folder, tmp_path):
    path = tmp_path / "t.toml"
    path.write_bytes(b'a = """x\r\ny"""\r\n')  # CRLF kept, as tomllib.load keeps it
    with path.open("rb") as handle:
        assert read_table(path) == tomllib.load(handle)


def test_a_whole_file_replaces_the_old_one_and_a_place_that_cannot_take_it_leaves_nothing_behind(tmp_path):
    """The writer shared by the result, table and class-code caches: renamed into place,
    and where that fails (a folder in the way, a file where the folder should be) no error
    and no temporary file."""
    target = tmp_path / "entry.json"
    target.write_bytes(b"old")
    resources.write_whole(target, b"new")
    assert target.read_bytes() == b"new"
    blocked = tmp_path / "blocked.json"
    blocked.mkdir()
    resources.write_whole(blocked, b"data")
    resources.write_whole(target / "under-a-file.json", b"data")
    assert sorted(path.name for path in tmp_path.iterdir()) == ["blocked.json", "entry.json"] and blocked.is_dir()
