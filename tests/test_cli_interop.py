"""`assur import` and `assur export`: the commands around assur.interop. A failure is one ``error:`` line and exit 1;
outputs are written atomically and a special file is written through, never replaced."""
import json
import os
import stat
from pathlib import Path

import pytest

import assur
from assur.cli.exchange import WRITERS
from assur.cli.main import main
from assur.interop import EXPORTERS
from assur.interop.compare import differences

ROOT = Path(__file__).resolve().parents[1]
JANSEN = ROOT / "examples" / "jansen.toml"
LINKS = ROOT / "tests" / "crosscheck" / "data" / "pmks_fixture_urls.tsv"


def one_error(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: "), err
    return err[0]


def test_the_export_table_is_the_python_api_s():
    # the interchange formats, plus mjcf (a MuJoCo model, written only: tests/test_mjcf.py)
    assert [k for k in WRITERS if k != "mjcf"] == list(EXPORTERS)
    assert all(WRITERS[k]() is EXPORTERS[k][0]() for k in EXPORTERS)


@pytest.mark.parametrize("fmt", list(EXPORTERS))
def test_export_then_import_gives_the_mechanism_back(fmt, tmp_path, capsys):
    src = ROOT / "examples" / "crank_rocker.toml"
    out = tmp_path / f"m{EXPORTERS[fmt][1]}"
    assert main(["export", str(src), "--to", fmt, str(out)]) == 0
    printed = capsys.readouterr().out
    if fmt == "pmks":
        link = printed.split("PMKS+ link: ", 1)[1].strip()
        assert link.startswith("https://app.pmksplus.com/?")
        assert main(["import", link, "-o", str(tmp_path / "from_link.toml")]) == 0   # the link opens the same
    back = tmp_path / "back.toml"
    assert main(["import", str(out), "-o", str(back)]) == 0
    assert "wrote" in capsys.readouterr().out
    tol = 1e-3 if fmt == "pmks" else 1e-9
    assert differences(assur.load(src), assur.load(back), tol=tol, speeds=fmt != "pmks") == []


def test_import_reads_a_link_given_as_text_and_standard_input(tmp_path, capsys, monkeypatch):
    name, gallery, link = next(line.split("\t") for line in LINKS.read_text().splitlines()
                               if line.startswith("Jansen leg"))
    out = tmp_path / "jansen.toml"
    assert main(["import", link, "-o", str(out)]) == 0
    m = assur.load(out)
    assert len(m.points) == 8 and m.units.length == "cm"
    import io
    monkeypatch.setattr("sys.stdin", io.StringIO(link))
    assert main(["import", "-", "-o", str(tmp_path / "stdin.toml")]) == 0
    assert differences(m, assur.load(tmp_path / "stdin.toml")) == []


def test_import_prints_what_it_leaves_out(tmp_path, capsys):
    doc = {"name": "arc", "joints": [{"id": "O", "type": "ground", "position": [0, 0]},
                                      {"id": "D", "type": "ground", "position": [4, 0]},
                                      {"id": "B", "type": "revolute", "position": [1, 0]},
                                      {"id": "C", "type": "revolute", "position": [2.5, 2.6]}],
           "links": [{"id": "ground", "type": "ground", "joints": ["O", "D"]},
                     {"id": "crank", "type": "arc_driver", "joints": ["O", "B"], "motor_joint": "O",
                      "arc_start": 0.0, "arc_end": 1.0},
                     {"id": "BC", "type": "link", "joints": ["B", "C"]},
                     {"id": "CD", "type": "link", "joints": ["C", "D"]}]}
    src = tmp_path / "arc.json"
    src.write_text(json.dumps(doc))
    assert main(["import", str(src), "-o", str(tmp_path / "arc.toml"), "--units", "mm"]) == 0
    err = capsys.readouterr().err
    assert "warning: pylinkage mechanism: arc_driver 'crank' oscillates" in err
    assert assur.load(tmp_path / "arc.toml").units.length == "mm"


@pytest.mark.parametrize("args,message", [
    (["import", "https://app.pmksplus.com/?2v.Ay,1E8.5,0.1011.6A,A,0,VG", "-o", "{tmp}/x.toml"], "truncated"),
    (["import", "{tmp}/foreign.json", "-o", "{tmp}/x.toml"], "not a pylinkage mechanism"),
    (["import", "{tmp}/missing.json", "-o", "{tmp}/x.toml"], "no such file"),
    (["import", "hello there", "-o", "{tmp}/x.toml"], "cannot tell the format"),
    (["import", str(JANSEN), "-o", "{tmp}/x.toml"], "already an assur/1 mechanism file"),
    (["export", str(ROOT / "examples" / "rssr.toml"), "--to", "pylinkage", "{tmp}/x.json"], "dimension: a spatial"),
    (["export", str(ROOT / "examples" / "lever_manipulator.toml"), "--to", "pmks", "{tmp}/x.pmks"],
     "actuators.drive_rod"),
    (["export", str(JANSEN), "--to", "fourbar", "{tmp}/x.ron"], "links:"),
    (["export", str(JANSEN), "--to", "pmks", "{tmp}"], "is a directory"),
])
def test_failures_are_one_located_error_line(args, message, tmp_path, capsys):
    (tmp_path / "foreign.json").write_text('{"type": "FeatureCollection", "features": []}')
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    assert main(args) == 1
    assert message in one_error(capsys)
    assert not (tmp_path / "x.toml").exists() and not (tmp_path / "x.json").exists()


def test_a_failed_export_leaves_an_existing_file_untouched(tmp_path, capsys):
    out = tmp_path / "keep.ron"
    out.write_text("mine\n")
    assert main(["export", str(JANSEN), "--to", "fourbar", str(out)]) == 1
    one_error(capsys)
    assert out.read_text() == "mine\n"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.ron"]       # no temporary left behind


def test_export_writes_through_a_fifo_without_replacing_it(tmp_path, capsys):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    import threading
    got = {}

    def reader():
        with open(fifo, encoding="utf-8") as fh:
            got["text"] = fh.read()
    t = threading.Thread(target=reader)
    t.start()
    assert main(["export", str(JANSEN), "--to", "pyslvs", str(fifo)]) == 0
    t.join(10)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode) and "mechanism: M[" in got["text"]


def test_import_output_must_be_toml(tmp_path, capsys):
    with pytest.raises(SystemExit):
        from assur.cli.main import build_parser
        build_parser().parse_args(["import", "x", "-o", str(tmp_path / "x.json")])
