"""Safe outputs (io/output.py): special files are written through and never replaced, symlinks are followed,
an output directory holds exactly one run's files, and an interrupted run's leftovers are cleaned."""
import os
import stat
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from assur.errors import OutputError
from assur.io.output import MARKER, atomic_directory, atomic_file


def _write(path, text):
    with atomic_file(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")


def test_a_regular_file_is_replaced_and_no_temporary_is_left(tmp_path):
    f = tmp_path / "out.csv"
    f.write_text("old")
    _write(f, "new")
    assert f.read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_a_fifo_is_written_through_and_stays_a_fifo(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_text()))
    reader.start()
    _write(fifo, "a,b\n1,2\n")
    reader.join(timeout=10)
    assert got == ["a,b\n1,2\n"]
    assert stat.S_ISFIFO(fifo.lstat().st_mode)


@pytest.mark.skipif(not hasattr(os, "getuid") or os.getuid() != 0, reason="making a device node needs root")
def test_a_character_device_is_written_through_and_stays_a_device(tmp_path):
    null = tmp_path / "null"                      # a private copy of /dev/null (major 1, minor 3)
    os.mknod(null, stat.S_IFCHR | 0o666, os.makedev(1, 3))
    _write(null, "discarded")
    assert stat.S_ISCHR(null.lstat().st_mode)


def test_the_cli_csv_to_dev_null_keeps_dev_null_a_device(tmp_path):
    """``assur solve F --csv /dev/null`` writes through the system's null device."""
    example = Path(__file__).resolve().parents[1] / "examples" / "crank_rocker.toml"
    before = os.stat("/dev/null")
    r = subprocess.run([sys.executable, "-m", "assur", "solve", str(example), "--steps", "8", "--csv", "/dev/null"],
                       capture_output=True, encoding="utf-8")
    assert r.returncode == 0, r.stderr
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and (after.st_ino, after.st_rdev) == (before.st_ino, before.st_rdev)


def test_a_symlink_is_followed_and_stays_a_link(tmp_path):
    target = tmp_path / "real.csv"
    target.write_text("old")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    _write(link, "new")
    assert link.is_symlink() and target.read_text() == "new"


def test_dash_is_standard_output(capfdbinary):
    _write("-", "to stdout\n")
    assert capfdbinary.readouterr().out == b"to stdout\n"


@pytest.mark.parametrize("path", [""])
def test_an_empty_path_is_refused(path):
    with pytest.raises(OutputError, match="empty"):
        _write(path, "x")


def test_a_failure_names_the_users_path_not_the_temporary(tmp_path):
    with pytest.raises(OutputError) as info:
        _write(tmp_path / "missing" / "out.csv", "x")
    assert str(tmp_path / "missing") in str(info.value) and ".tmp" not in str(info.value)


def _run(out, files):
    with atomic_directory(out) as tmp:
        for name, text in files.items():
            (tmp / name).write_text(text)


def test_an_output_directory_holds_exactly_one_runs_files(tmp_path):
    out = tmp_path / "out"
    _run(out, {"a.csv": "1", "b.csv": "2"})
    _run(out, {"a.csv": "3"})
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "a.csv"]
    assert (out / "a.csv").read_text() == "3"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_directory_of_other_files_is_never_replaced(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    with pytest.raises(OutputError, match="not an earlier output"):
        _run(out, {"a.csv": "1"})
    assert (out / "thesis.tex").read_text() == "precious"


def test_an_empty_existing_directory_is_used(tmp_path):
    out = tmp_path / "empty"
    out.mkdir()
    _run(out, {"a.csv": "1"})
    assert (out / "a.csv").read_text() == "1"


def test_temporaries_of_a_killed_run_are_removed_on_the_next_run(tmp_path):
    """A process that no longer runs: a child that has exited (its pid is free again)."""
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, encoding="utf-8")
    pid = int(dead.stdout)
    stale = tmp_path / f".out.{pid}.abc123.tmp"
    stale.mkdir()
    (stale / "half.csv").write_text("half")
    mine = tmp_path / f".out.{os.getpid()}.zzz.tmp"       # this process's own: kept
    mine.mkdir()
    _run(tmp_path / "out", {"a.csv": "1"})
    assert not stale.exists() and mine.exists()


def test_a_failing_run_leaves_the_previous_output(tmp_path):
    out = tmp_path / "out"
    _run(out, {"a.csv": "1"})
    with pytest.raises(RuntimeError):
        with atomic_directory(out) as tmp:
            (tmp / "b.csv").write_text("2")
            raise RuntimeError("midway")
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "a.csv"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


@pytest.mark.parametrize("args", [["report", "{f}", "-o", ""], ["solve", "{f}", "--steps", "4", "--csv", ""],
                                  ["plot", "{f}", "-o", ""]])
def test_the_cli_refuses_an_empty_output_path(args, tmp_path):
    """``-o ""`` once meant the current directory."""
    example = str(Path(__file__).resolve().parents[1] / "examples" / "crank_rocker.toml")
    r = subprocess.run([sys.executable, "-m", "assur", *[a.format(f=example) for a in args]], capture_output=True,
                       encoding="utf-8", cwd=tmp_path)
    assert r.returncode == 2 and "the path is empty" in r.stderr and "Traceback" not in r.stderr
    assert list(tmp_path.iterdir()) == []


# -- standard output into a pipe -------------------------------------------------------------------------------
SLIDER = Path(__file__).resolve().parents[1] / "examples" / "slider_crank.toml"
LEG = Path(__file__).resolve().parents[1] / "examples" / "walker_fourbar.toml"


@pytest.mark.parametrize("csv", ["-", "/dev/stdout"])
@pytest.mark.parametrize("command", [["solve", str(SLIDER), "--steps", "50"], ["forces", str(LEG), "--steps", "50"]])
def test_csv_to_standard_output_in_a_pipe_is_the_csv_alone(csv, command):
    """``--csv /dev/stdout`` into a pipe once failed (the link resolves to ``pipe:[…]``, which cannot be opened);
    with the CSV on standard output, the report lines go to standard error so the pipe carries the table alone."""
    r = subprocess.run([sys.executable, "-m", "assur", *command, "--csv", csv], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, encoding="utf-8", timeout=300)
    assert r.returncode == 0, r.stderr
    rows = r.stdout.splitlines()
    assert len(rows) == 1 + 50 and all(len(row.split(",")) == len(rows[0].split(",")) for row in rows)
    float(rows[1].split(",")[0])                           # data, not a report line
    assert f"wrote {csv}" in r.stderr and "error" not in r.stderr


@pytest.mark.parametrize("command", [["solve", str(SLIDER), "--steps", "20000", "--csv", "-"],
                                     ["solve", str(SLIDER), "--steps", "20000", "--csv", "/dev/stdout"],
                                     ["analyze", str(LEG), "--json"]])
def test_a_reader_that_closes_the_pipe_ends_the_command_quietly(command):
    """``assur solve F --csv - | head -5``: the reader takes five lines and closes the pipe; the command ends
    with status 0 and no error line, as Unix tools do (it once printed 'error: cannot write -: Broken pipe')."""
    p = subprocess.Popen([sys.executable, "-m", "assur", *command], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    head = [p.stdout.readline() for _ in range(5)]
    p.stdout.close()                                       # as `head -5` exits
    err = p.stderr.read().decode()
    assert p.wait(timeout=300) == 0, err
    assert all(head) and "error" not in err and "Traceback" not in err
