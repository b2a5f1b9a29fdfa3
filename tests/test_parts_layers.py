"""The layer program (scipy's HiGHS) against an independent brute force, its clique bound and its certificate."""
import itertools

import numpy as np
import pytest

from assur.parts.layers import (Layout, PinNeed, Program, Unstackable, feasible, max_clique, solve_layers)


def brute_force_minimum(program: Program, limit: int = 6):
    """The fewest layers of ``program`` by enumerating every assignment of its groups to layers and every choice
    of frame ends, checked against the rules written out here (not by assur.parts.layers):

    - two conflicting groups never share a layer;
    - a pin spans from the lowest to the highest thing it holds (a frame end: the base, below every layer, or the
      top plate, above the last used layer); a group that covers it is never strictly inside that span;
    - two pins that come close never both fill the gap between the same two adjacent levels."""
    n = len(program.groups)
    for L in range(1, limit + 1):
        for lay in itertools.product(range(L), repeat=n):
            if len(set(lay)) != L:
                continue
            if any(lay[g] == lay[h] for g, h in program.edges):
                continue
            for side in itertools.product((0, 1), repeat=len(program.sides)):
                spans = []
                ok = True
                for pin in program.pins:
                    levels = [lay[g] for g in pin.groups] + [L if side[f] else -1 for f in pin.ends]
                    lo, hi = min(levels), max(levels)
                    if any(lo < lay[g] < hi for g in pin.blocked):
                        ok = False
                        break
                    spans.append((lo, hi))
                if ok and all(max(spans[a][0], spans[b][0]) >= min(spans[a][1], spans[b][1])
                              for a, b in program.pin_edges):
                    return L
    return None


def random_program(rng, n_groups):
    edges = {(g, h) for g in range(n_groups) for h in range(g + 1, n_groups) if rng.random() < 0.35}
    sides = [f"end{k}" for k in range(rng.integers(0, 3))]
    pins = []
    for j in range(rng.integers(1, 4)):
        held = sorted(rng.choice(n_groups, size=min(n_groups, int(rng.integers(1, 3))), replace=False).tolist())
        ends = [int(rng.integers(len(sides)))] if sides and rng.random() < 0.6 else []
        if len(held) + len(ends) < 2:
            ends = ends or ([0] if sides else [])
            if len(held) + len(ends) < 2:
                held = sorted(set(held) | {int((held[0] + 1) % n_groups)})
        blocked = [g for g in range(n_groups) if g not in held and rng.random() < 0.3]
        pins.append(PinNeed(f"pin{j}", held, ends, blocked))
    pin_edges = [(a, b) for a in range(len(pins)) for b in range(a + 1, len(pins)) if rng.random() < 0.3]
    return Program([[f"g{g}"] for g in range(n_groups)], edges, pins, pin_edges, sides)


@pytest.mark.parametrize("seed", range(24))
def test_the_integer_program_finds_the_brute_force_minimum(seed):
    rng = np.random.default_rng(seed)
    program = random_program(rng, int(rng.integers(2, 6)))
    expected = brute_force_minimum(program)
    if expected is None:
        with pytest.raises(Unstackable):
            solve_layers(program, time_limit=20)
        return
    layout, cert = solve_layers(program, time_limit=20)
    assert layout.layers == expected
    assert cert.proven and cert.status == "optimal"
    assert cert.bound <= expected
    assert feasible(program, layout)


def test_the_clique_bound_is_the_largest_set_of_pairwise_conflicts():
    # a 5-cycle has cliques of 2 but needs 3 colours: the program proves 3 although the bound says 2
    edges = {(0, 1), (1, 2), (2, 3), (3, 4), (0, 4)}
    program = Program([[f"p{g}"] for g in range(5)], edges, [], [], [])
    assert len(max_clique(program)) == 2
    layout, cert = solve_layers(program)
    assert layout.layers == 3 and cert.bound == 2
    assert cert.proven and cert.exhaustive is True      # no layout with 2 layers, found by the exhaustive search


def test_a_clique_larger_than_the_limit_is_unstackable_naming_it():
    edges = {(0, 1), (0, 2), (1, 2), (2, 3)}
    program = Program([["a"], ["b"], ["c"], ["d"]], edges, [], [], [])
    with pytest.raises(Unstackable) as exc:
        solve_layers(program, max_layers=2)
    assert exc.value.clique and sorted(exc.value.groups) == [0, 1, 2]


def test_couplers_covering_each_others_crank_pins_cannot_be_stacked():
    # the pattern of a six-bar leg with two crank pins (walker_sixbar_beta1_60): crank 0 driven at a frame end,
    # couplers 1 and 2 on its pins; both couplers pass over the crank's axis and each over the other's pin
    program = Program([["crank"], ["bm"], ["na"]], {(0, 1), (0, 2), (1, 2)},
                      [PinNeed("shaft", [0], [0], [1, 2]), PinNeed("B", [0, 1], [], [2]), PinNeed("N", [0, 2], [], [1])],
                      [], ["end of shaft"])
    assert brute_force_minimum(program) is None
    with pytest.raises(Unstackable) as exc:
        solve_layers(program)
    assert not exc.value.clique
    assert sorted(exc.value.groups) == [0, 1, 2]
    # without the shaft's frame end (a crank driven from elsewhere) the couplers go on either side of the crank
    free = Program(program.groups, program.edges, program.pins[1:], [], [])
    assert solve_layers(free)[0].layers == brute_force_minimum(free) == 3


def test_feasible_checks_each_rule():
    program = Program([["a"], ["b"], ["c"]], {(0, 1)}, [PinNeed("ab", [0, 2], [], [1])], [], [])
    assert feasible(program, Layout(np.array([0, 1, 0]), np.zeros(0, int), 2))
    assert not feasible(program, Layout(np.array([0, 0, 1]), np.zeros(0, int), 2))      # a conflict shares a layer
    assert not feasible(program, Layout(np.array([0, 1, 2]), np.zeros(0, int), 3))      # the pin crosses b
