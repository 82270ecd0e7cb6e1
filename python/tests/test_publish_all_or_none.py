"""Outputs moved into place all or none (``common.Outputs.publish``): a move that fails
after another has been made puts back the file replaced, removes the files made where
there were none, and leaves no temporary or set-aside file; with or without hard links
(without them, the old files are moved aside instead of linked). The old contents are
written by the test, and compared byte for byte."""

import errno
import os
from pathlib import Path

import pytest

from penedge.cli import common, main


def no_hard_links(monkeypatch):
    """A file system without hard links: every os.link fails as on FAT or some mounts."""

    def link(*args, **kwargs):
        raise OSError(errno.EPERM, "Operation not permitted")

    monkeypatch.setattr(os, "link", link)


def failing_move(monkeypatch, fail_at, targets):
    """os.replace fails at the `fail_at`-th move of a new output onto one of `targets`
    (1-based); every other rename goes through. Returns the list of targets moved onto."""
    real = os.replace
    moves = []

    def replace(src, dst, *args, **kwargs):
        if Path(dst) in targets and Path(src).suffix == ".tmp":  # a staged output
            moves.append(Path(dst))
            if len(moves) == fail_at:
                raise OSError(errno.ENOSPC, "No space left on device", str(src))
        return real(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", replace)
    return moves


def stage(outputs, path, replace, content):
    staged = outputs.staged(common.Target(path, replace))
    staged.write(lambda handle: handle.write(content))


def files(folder):
    return {p.name: p.read_bytes() for p in folder.iterdir()}


@pytest.mark.parametrize("links", [True, False], ids=["hard links", "no hard links"])
def test_a_failed_second_move_leaves_every_output_as_it_was(tmp_path, monkeypatch, links):
    a, b = tmp_path / "a.png", tmp_path / "b.html"
    a.write_bytes(b"old a")
    b.write_bytes(b"old b")
    before = files(tmp_path)
    if not links:
        no_hard_links(monkeypatch)
    moves = failing_move(monkeypatch, 2, {a, b})
    with common.Outputs() as outputs:
        stage(outputs, a, True, b"new a")
        stage(outputs, b, True, b"new b")
        with pytest.raises(OSError, match="No space left") as info:
            outputs.publish()
    assert moves == [a, b]  # the first move was made, the second failed
    assert info.value.filename == str(b)  # named as the user named it
    assert files(tmp_path) == before  # old a back, old b kept, nothing else left
    # Once the moves go through, both are replaced and no set-aside old file is left.
    monkeypatch.undo()
    if not links:
        no_hard_links(monkeypatch)
    with common.Outputs() as outputs:
        stage(outputs, a, True, b"new a")
        stage(outputs, b, True, b"new b")
        assert outputs.publish() == [a, b]
    assert files(tmp_path) == {"a.png": b"new a", "b.html": b"new b"}


@pytest.mark.parametrize("links", [True, False], ids=["hard links", "no hard links"])
def test_files_made_where_there_were_none_are_removed_again(tmp_path, monkeypatch, links):
    # A new file (c.csv), a default name that may not be replaced (d.png exists: d-1.png
    # is made), an existing file replaced (a.png), then the move that fails (b.html).
    a, b, c, d = (tmp_path / n for n in ("a.png", "b.html", "c.csv", "d.png"))
    for path in (a, b, d):
        path.write_bytes(b"old " + path.name.encode())
    before = files(tmp_path)
    if not links:
        no_hard_links(monkeypatch)
    failing_move(monkeypatch, 2, {a, b})
    with common.Outputs() as outputs:
        stage(outputs, c, True, b"new c")
        stage(outputs, d, False, b"new d")
        stage(outputs, a, True, b"new a")
        stage(outputs, b, True, b"new b")
        with pytest.raises(OSError, match="No space left"):
            outputs.publish()
    assert files(tmp_path) == before


def test_a_failure_of_the_show_command_between_two_moves_changes_no_output(
    tmp_path, monkeypatch, capsys
):
    pytest.importorskip("matplotlib")
    pytest.importorskip("plotly")
    import penedge

    monkeypatch.chdir(tmp_path)
    penedge.paper_example(1).write_json(tmp_path / "blocks.json")
    (tmp_path / "ok.png").write_bytes(b"old picture")
    (tmp_path / "ok.html").write_bytes(b"old view")
    before = files(tmp_path)
    failing_move(monkeypatch, 2, {Path("ok.png"), Path("ok.html")})
    assert main(["show", "blocks.json", "-o", "ok.png", "--html-out", "ok.html", "-q"]) == 1
    assert capsys.readouterr().err == "penedge: error: ok.html: No space left on device\n"
    assert files(tmp_path) == before


def test_an_old_file_that_cannot_be_put_back_is_kept_and_named(tmp_path, monkeypatch):
    a, b = tmp_path / "a.png", tmp_path / "b.html"
    a.write_bytes(b"old a")
    b.write_bytes(b"old b")
    failing_move(monkeypatch, 2, {a, b})
    real = os.replace

    def no_way_back(src, dst, *args, **kwargs):
        if Path(src).suffix == ".old":  # putting an old file back
            raise OSError(errno.EIO, "Input/output error", str(src))
        return real(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", no_way_back)
    with common.Outputs() as outputs:
        stage(outputs, a, True, b"new a")
        stage(outputs, b, True, b"new b")
        with pytest.raises(common.CommandError) as info:
            outputs.publish()
    kept = [p for p in tmp_path.iterdir() if p.suffix == ".old"]
    assert len(kept) == 1
    assert kept[0].read_bytes() == b"old a"
    message = str(info.value)
    assert message.startswith(f"{b}: No space left on device; could not put back every file: ")
    assert message.endswith(f"the old {a} is kept as {kept[0]}")
    assert b.read_bytes() == b"old b"
