"""`assur design` as a user runs it: it prints a tokened loopback URL, serves the page, stops cleanly on Ctrl-C,
and refuses bad input with one error line."""
import re
import signal
import socket
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from assur.cli.main import main

from conftest import as_from_a_shell

ROOT = Path(__file__).resolve().parents[1]
pytest.importorskip("starlette")


def _start(*args):
    p = subprocess.Popen([sys.executable, "-m", "assur", "design", *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, encoding="utf-8", preexec_fn=as_from_a_shell)
    line = p.stdout.readline()
    return p, line


def test_design_prints_a_loopback_url_with_a_token_serves_the_page_and_stops_on_ctrl_c():
    p, line = _start(str(ROOT / "examples" / "walker_fourbar.toml"), "--no-browser")
    try:
        m = re.fullmatch(r"assur design: (http://127\.0\.0\.1:(\d+)/\?token=([\w-]{20,}))\n", line)
        assert m, line
        with urllib.request.urlopen(m.group(1), timeout=20) as r:
            page = r.read().decode()
        assert r.status == 200 and 'type="module"' in page
        with pytest.raises(urllib.error.HTTPError) as exc:
            urllib.request.urlopen(f"http://127.0.0.1:{m.group(2)}/", timeout=20)
        assert exc.value.code == 403
    finally:
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=30)
    assert p.returncode == 0, err
    assert "stopped" in out and "Traceback" not in err


def test_two_servers_get_different_ports_and_tokens():
    a, la = _start(str(ROOT / "examples" / "jansen.toml"), "--no-browser")
    b, lb = _start(str(ROOT / "examples" / "jansen.toml"), "--no-browser", "--port", "0")
    try:
        (ua,), (ub,) = re.findall(r"http://\S+", la), re.findall(r"http://\S+", lb)
        assert ua != ub and ua.split("token=")[1] != ub.split("token=")[1]
    finally:
        for p in (a, b):
            p.send_signal(signal.SIGINT)
            p.communicate(timeout=30)


def test_design_refuses_bad_input(tmp_path, capsys):
    assert main(["design", str(tmp_path / "missing.toml"), "--no-browser"]) == 1
    assert capsys.readouterr().err.startswith("error: no such file")
    assert main(["design", str(ROOT / "examples" / "jansen.toml"), "--port", "70000", "--no-browser"]) == 1
    assert "--port" in capsys.readouterr().err
    bad = tmp_path / "bad.toml"
    bad.write_text('format = "assur/1"\n[units]\nlength = "mm"\nangle = "deg"\n[points]\nA = [0, "x"]\n')
    assert main(["design", str(bad), "--no-browser"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error:") and "Traceback" not in err
    with socket.socket() as busy:                      # a port that is taken: one error line, no traceback
        busy.bind(("127.0.0.1", 0))
        busy.listen(1)
        port = busy.getsockname()[1]
        assert main(["design", str(ROOT / "examples" / "jansen.toml"), "--port", str(port), "--no-browser"]) == 1
        err = capsys.readouterr().err
        assert err.startswith("error: cannot serve on 127.0.0.1:") and "Traceback" not in err
