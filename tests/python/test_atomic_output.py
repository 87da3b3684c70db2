"""atomic_output: what may be replaced, temporaries and their clean-up, concurrent writers."""

import json
import os
import subprocess
import sys
import threading

import pytest

from hairlod import atomic_output
from hairlod.atomic_output import OutputFolderError

KIND = "hairlod-test/"


def write_asset(files):
    """A write() for replace_folder: a manifest of kind KIND naming `files`, and those files."""
    def write(folder):
        for name, text in files.items():
            with open(os.path.join(folder, name), "w") as stream:
                stream.write(text)
        manifest = {"format": KIND + "1", "tables": [{"file": name} for name in files]}
        with open(os.path.join(folder, "manifest.json"), "w") as stream:
            json.dump(manifest, stream)
        return manifest
    return write


def test_writes_a_new_folder_and_replaces_only_its_own_kind(tmp_path):
    target = tmp_path / "out"
    atomic_output.replace_folder(target, KIND, write_asset({"a.txt": "1"}))
    assert sorted(os.listdir(target)) == ["a.txt", "manifest.json"]
    atomic_output.replace_folder(target, KIND, write_asset({"b.txt": "2"}))
    assert sorted(os.listdir(target)) == ["b.txt", "manifest.json"]
    with pytest.raises(OutputFolderError, match="not hairlod-other/ folder"):
        atomic_output.replace_folder(target, "hairlod-other/", write_asset({}))
    assert sorted(os.listdir(tmp_path)) == ["out"]


@pytest.mark.parametrize("damage, reason", [
    (lambda t: (t / "notes.txt").write_text("mine"), r"files hairlod did not write there \(notes.txt\)"),
    (lambda t: (t / "manifest.json").unlink(), "no manifest.json"),
    (lambda t: (t / "manifest.json").write_text("[[[["), "not one hairlod wrote"),
    (lambda t: (t / "manifest.json").write_text('{"format": "mine"}'), "not a hairlod-test/ manifest"),
    (lambda t: (t / "sub").mkdir(), r"did not write there \(sub\)"),
])
def test_refuses_a_folder_holding_anything_else_and_leaves_it(tmp_path, damage, reason):
    target = tmp_path / "out"
    atomic_output.replace_folder(target, KIND, write_asset({"a.txt": "1"}))
    damage(target)
    before = sorted(os.listdir(target))
    called = []
    with pytest.raises(OutputFolderError, match=reason) as error:
        atomic_output.replace_folder(target, KIND, lambda folder: called.append(folder))
    assert str(error.value).startswith(f"{target}: exists and is not")
    assert called == [], "refused before any work"
    assert sorted(os.listdir(target)) == before
    assert sorted(os.listdir(tmp_path)) == ["out"]


def test_an_empty_folder_is_replaced(tmp_path):
    (tmp_path / "out").mkdir()
    atomic_output.replace_folder(tmp_path / "out", KIND, write_asset({"a.txt": "1"}))
    assert (tmp_path / "out" / "a.txt").read_text() == "1"


def test_never_a_file_nor_a_folder_holding_an_input(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(OutputFolderError, match="is not a folder"):
        atomic_output.replace_folder(tmp_path / "notes.txt", KIND, write_asset({}), force=True)
    assert (tmp_path / "notes.txt").read_text() == "mine"
    source = tmp_path / "in" / "hair.hair"
    source.parent.mkdir()
    source.write_text("hair")
    for target in (tmp_path / "in", tmp_path):
        with pytest.raises(OutputFolderError, match="would replace the input"):
            atomic_output.replace_folder(target, KIND, write_asset({}), force=True, inputs=[source])
    assert source.read_text() == "hair"


def test_force_replaces_a_foreign_folder_but_never_cwd_home_or_root(tmp_path, monkeypatch):
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "x").write_text("x")
    atomic_output.replace_folder(foreign, KIND, write_asset({"a.txt": "1"}), force=True)
    assert sorted(os.listdir(foreign)) == ["a.txt", "manifest.json"]
    home = tmp_path / "home"
    (home / "work").mkdir(parents=True)
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(home / "work")
    for protected in (home / "work", home, tmp_path, "/"):
        with pytest.raises(OutputFolderError, match="current, home or root"):
            atomic_output.replace_folder(protected, KIND, write_asset({}), force=True)
    assert os.path.isdir(home / "work")


def test_a_failed_write_leaves_the_old_folder_and_names_the_target(tmp_path):
    target = tmp_path / "out"
    atomic_output.replace_folder(target, KIND, write_asset({"a.txt": "1"}))

    def failing(folder):
        raise ValueError(f"{os.path.join(folder, 'level0.hair')}: cannot write")

    with pytest.raises(ValueError) as error:
        atomic_output.replace_folder(target, KIND, failing)
    assert str(error.value) == f"{target}/level0.hair: cannot write"
    assert (target / "a.txt").read_text() == "1"
    assert sorted(os.listdir(tmp_path)) == ["out"]


def test_folders_and_files_get_the_umask_modes(tmp_path):
    old = os.umask(0o027)
    try:
        atomic_output.replace_folder(tmp_path / "out", KIND, write_asset({}))
        with atomic_output.replacing_file(tmp_path / "file.txt") as temporary:
            open(temporary, "w").close()
    finally:
        os.umask(old)
    assert os.stat(tmp_path / "out").st_mode & 0o777 == 0o750
    assert os.stat(tmp_path / "file.txt").st_mode & 0o777 == 0o640


def test_replacing_file_keeps_the_old_file_on_failure(tmp_path):
    path = tmp_path / "image.png"
    path.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_output.replacing_file(path) as temporary:
            open(temporary, "w").write("half")
            raise RuntimeError("drawing failed")
    assert path.read_text() == "old" and sorted(os.listdir(tmp_path)) == ["image.png"]
    with atomic_output.replacing_file(path) as temporary:
        open(temporary, "w").write("new")
    assert path.read_text() == "new" and sorted(os.listdir(tmp_path)) == ["image.png"]
    with pytest.raises(OutputFolderError, match="is a folder"):
        with atomic_output.replacing_file(tmp_path):
            pass


def dead_pid():
    """The id of a process that has ended."""
    child = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    return int(child.stdout)


def test_stale_temporaries_are_removed_and_live_ones_kept(tmp_path):
    target = tmp_path / "out"
    stale_folder = tmp_path / f".out.hairlod-{dead_pid()}-00ff.tmp"
    stale_folder.mkdir()
    (stale_folder / "level0.hair").write_text("partial")
    # The parent process is alive and older than this temporary: a concurrent writer, kept.
    live = tmp_path / f".out.hairlod-{os.getppid()}-abcd.tmp"
    live.write_text("in progress")
    # A running process that started after the temporary was last changed reuses an old id: stale.
    reused = tmp_path / f".out.hairlod-{os.getppid()}-beef.tmp"
    reused.write_text("old")
    os.utime(reused, (1, 1))
    other = tmp_path / f".other.hairlod-{dead_pid()}-00ff.tmp"
    other.write_text("another target's")
    removed = atomic_output.remove_stale_temporaries(target)
    assert sorted(removed) == sorted([str(stale_folder), str(reused)])
    assert sorted(os.listdir(tmp_path)) == sorted([live.name, other.name])


def test_own_temporaries_are_removed_for_a_signal_handler(tmp_path):
    path = atomic_output.temporary_path(tmp_path / "out")
    os.mkdir(path)
    atomic_output.remove_own_temporaries()
    assert os.listdir(tmp_path) == []


def test_concurrent_writers_end_with_one_complete_folder(tmp_path):
    target = tmp_path / "out"
    barrier = threading.Barrier(6)
    errors = []

    def writer(index):
        def write(folder):
            barrier.wait()
            return write_asset({f"{index}.txt": str(index) * 1000})(folder)
        try:
            atomic_output.replace_folder(target, KIND, write)
        except Exception as error:  # collected: the test fails on any
            errors.append(error)

    threads = [threading.Thread(target=writer, args=(i,)) for i in range(6)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == []
    names = sorted(os.listdir(target))
    assert len(names) == 2 and "manifest.json" in names
    written = json.loads((target / "manifest.json").read_text())["tables"][0]["file"]
    assert names == sorted([written, "manifest.json"])
    assert sorted(os.listdir(tmp_path)) == ["out"]
