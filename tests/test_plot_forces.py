"""The force figures (assur.plot.forces, ``assur plot --forces``) and Zhukovsky's lever
(assur.kinetostatics.lever).

The lever's reference is the principle of virtual power (Zhukovsky's theorem): the moment about the pole of
the applied loads carried to the turned velocity plan equals the driving effort times the input speed, so the
lever (built from the kinematics and the loads alone) is checked against the force solver's driver·q̇.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main
from assur.kinetostatics.lever import lever

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PNG = b"\x89PNG\r\n\x1a\n"


def _slider_crank(tmp_path):
    s = (EXAMPLES / "slider_crank.toml").read_text(encoding="utf-8")
    s = s.replace('length = 50\n', 'length = 50\nmass = "0.5 kg"\n', 1)
    s = s.replace('length = 150\n', 'length = 150\nmass = "1 kg"\n', 1)
    s += '\n[dynamics]\ngravity = [0, -9.81]\n\n[[loads]]\npoint = "B"\nforce = [-100, 20]\n'
    p = tmp_path / "sc.toml"
    p.write_text(s, encoding="utf-8")
    return p


def _crank_rocker(tmp_path):
    s = (EXAMPLES / "crank_rocker.toml").read_text(encoding="utf-8")
    s = s.replace('length = 40\n', 'length = 40\nmass = "0.2 kg"\n', 1)
    s = s.replace('length = 80\n', 'length = 80\nmass = "0.4 kg"\n', 1)
    s = s.replace('length = 120\n', 'length = 120\nmass = "0.8 kg"\ncom = "P"\n', 1)
    s += ('\n[dynamics]\ngravity = [0, -9.81]\n\n[[loads]]\nlink = "rocker"\ntorque = "3 N*m"\n'
          '\n[[loads]]\npoint = "P"\nforce = [0, -50]\n')
    p = tmp_path / "cr.toml"
    p.write_text(s, encoding="utf-8")
    return p


@pytest.mark.parametrize("make", [_slider_crank, _crank_rocker])
def test_lever_moment_is_driver_times_speed(tmp_path, make):
    plan = assur.compile(assur.load(make(tmp_path)))
    q = np.linspace(0.0, 2 * math.pi, 48, endpoint=False)[:, None]
    f = assur.forces(plan, None, q)
    lv = lever(plan, None, q)
    expected = f.driver[:, 0] * plan.speeds[0]
    ok = np.isfinite(expected)
    assert ok.all()
    scale = np.max(np.abs(expected))
    assert np.max(np.abs(lv.moment - expected)) <= 1e-9 * scale
    assert lv.images.shape == lv.forces.shape == (48, len(lv.bodies))


def test_lever_with_point_loads(tmp_path):
    plan = assur.compile(assur.load(_slider_crank(tmp_path)))
    q = np.linspace(0.0, 2 * math.pi, 12, endpoint=False)[:, None]
    extra = [("A", np.array([5.0, -7.0]), "rod")]        # A joins the crank and the rod: the rod carries it
    f = assur.forces(plan, None, q, point_loads=extra)
    lv = lever(plan, None, q, point_loads=extra)
    expected = f.driver[:, 0] * plan.speeds[0]
    assert np.max(np.abs(lv.moment - expected)) <= 1e-9 * np.max(np.abs(expected))


def _is_png(path):
    data = Path(path).read_bytes()
    return data[:8] == PNG and len(data) > 10_000


def test_python_figures(tmp_path):
    from assur.plot import forces as pf
    from assur.plot.draw import close
    plan = assur.compile(assur.load(_crank_rocker(tmp_path)))
    for name, fig in [("t", pf.torque_figure(plan, 72)), ("h", pf.hodograph_figure(plan, 72)),
                      ("a", pf.arrows_figure(plan, 1.0)), ("l", pf.lever_figure(plan, 1.0)),
                      ("all", pf.forces_figure(plan, 72))]:
        out = tmp_path / f"{name}.png"
        fig.savefig(out)
        close(fig)
        assert _is_png(out)


def test_cli_plot_forces(tmp_path, capsys):
    f = _slider_crank(tmp_path)
    out = tmp_path / "forces.png"
    assert main(["plot", str(f), "--forces", "--at", "45", "--steps", "72", "-o", str(out)]) == 0
    assert _is_png(out)
    assert main(["plot", str(f), "--forces", "--steps", "72", "-o", str(tmp_path / "f.svg")]) == 0
    assert (tmp_path / "f.svg").read_text(encoding="utf-8").lstrip().startswith("<?xml")
    capsys.readouterr()
    bad = tmp_path / "bad.png"
    assert main(["plot", str(f), "--at", "45", "-o", str(bad)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--at" in err[0] and "--forces" in err[0] and not bad.exists()
    assert main(["plot", str(f), "--forces", "--at", "x", "-o", str(bad)]) == 1
    assert "--at" in capsys.readouterr().err and not bad.exists()


def test_torque_and_power_at_constant_speed_are_one_curve_with_two_scales():
    """At a constant crank speed P = T·ω: once two curves on twin axes lay exactly on each other. Now one curve,
    the power as the right axis's scale, which must be the torque scale times the file's ω (27 rpm)."""
    from assur.plot.draw import close
    from assur.plot.forces import torque_figure
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    fig = torque_figure(plan, 72)
    try:
        fig.canvas.draw()
        data_lines = [ln for ax in fig.axes for ln in ax.get_lines() if len(ln.get_xdata()) > 2]
        assert len(data_lines) == 1                              # the torque alone (the zero line has 2 points)
        ax = fig.axes[0]
        [sec] = [c for c in ax.child_axes if "power" in c.get_ylabel()]
        omega = 27 * 2 * math.pi / 60                            # the file's crank speed, rad/s
        assert plan.speeds[0] == pytest.approx(omega)
        np.testing.assert_allclose(sec.get_ylim(), np.array(ax.get_ylim()) * omega, rtol=1e-9)
    finally:
        close(fig)
