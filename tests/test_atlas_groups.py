"""The atlas's mechanisms (inversions), drivers, Assur groups, dyad kinds and the identification of the examples.

Literature numbers, each with its source:

* Mechanisms (inversions) of the 1-DOF chains of revolute pairs: 6 links: 5 (the Watt I, II and Stephenson I,
  II, III six-bars), 8 links: 71, 10 links: 1834 — Tsai, *Mechanism Design: Enumeration of Kinematic Structures
  According to Function* (CRC 2001), the table of planar 1-DOF chains and mechanisms (4 links: 1 chain and 1
  mechanism; 6: 2 and 5; 8: 16 and 71; 10: 230 and 1834); the same numbers in Mruthyunjaya's survey
  ("Kinematic structure of mechanisms revisited", Mech. Mach. Theory 38, 2003).
* Baranov trusses: 3, 5, 7, 9 links: 1, 1, 3, 28. These are the numbers of the engineering tables of Baranov
  trusses as cited in docs/atlas.md (1, 3, 28, 633 for 5, 7, 9, 11 links; surveyed by N. Rojas, F. Thomas,
  "On closed-form solutions to the position analysis of Baranov trusses", Mech. Mach. Theory 50 (2012) 179–196,
  https://pdfslide.us/documents/on-closed-form-solutions-to-the-position-analysis-of-baranov-trusses.html,
  whose definition is this one: "a non-overconstrained linkage with zero-mobility from which an Assur group can
  be obtained by removing any of its links"); the tables themselves could not be read for these tests. So
  every truss count is also computed here independently: by trying every graph (3, 5, 7 links), by one binary
  link added to each 1-DOF chain of n − 1 links (7, 9, 11 links), and by nauty's geng over all graphs with
  the definition checked on all subsets in numpy (9, 11 links, where geng is installed).
  For 11 links all three give 562, not 633: of the 27 678 connected simple graphs with 11 vertices, 15 edges
  and minimum degree 2, exactly 562 have no rigid proper sub-chain. None of the looser readings tried gives
  633 while keeping 28 for 9 links (docs/atlas.md lists them), so what the 633 counts stays open.
* Assur groups (the trusses' link orbits): 2, 4, 6, 8 links: 1, 2, 10, 173 (10 links: 5438). No table of the
  literature was read for 6 links and more (P. Huang, H. Ding, "Structural synthesis of Assur groups with up to
  12 links and creation of their classified databases", Mech. Mach. Theory 145 (2020) 103668, obtains "a
  complete set of Assur groups with 2, 4, 6, 8, 10 and 12 links"; only its abstract was readable): the counts are checked by orbits computed here without nauty (every permutation
  for 6 links, networkx's VF2 automorphisms for 8).
* Dyad and the first groups of class III and IV: Artobolevsky, *Theory of Mechanisms and Machines* (the
  classification of Assur groups): one dyad (class II, order 2), a triad (class III, order 3) and a four-link
  group with a closed four-sided contour (class IV, order 2) of four links; the dyad's five kinds RRR, RRP,
  RPR, PRP, PPR (PPP excluded).
"""
import itertools
import shutil
import subprocess
import tomllib
from pathlib import Path

import networkx as nx
import numpy as np
import pytest

from assur.structure.atlas.graphs import ChainGraph, canonical
from assur.structure.atlas.groups import (assur_group_counts, assur_groups, baranov_trusses, dyad_kinds,
                                          is_baranov_truss, type_assignments)
from assur.structure.atlas.identify import identify
from assur.structure.atlas.mechanisms import driver_placements, inversion_at, inversions

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

FOUR_BAR = ChainGraph.of(4, [(0, 1), (1, 2), (2, 3), (0, 3)])
# Watt: ternary links 0 and 1 share a joint; two strings of two binary links join them
WATT = ChainGraph.of(6, [(0, 1), (0, 2), (2, 3), (3, 1), (0, 4), (4, 5), (5, 1)])
# Stephenson: ternary links 0 and 1 joined by strings of one, one and two binary links
STEPHENSON = ChainGraph.of(6, [(0, 2), (2, 1), (0, 3), (3, 1), (0, 4), (4, 5), (5, 1)])


def brute_automorphisms(g: ChainGraph):
    """All automorphisms by trying every permutation (small graphs only): independent of nauty."""
    es = set(g.edges)
    out = []
    for p in itertools.permutations(range(g.n)):
        if all(tuple(sorted((p[u], p[v]))) in es for u, v in g.edges):
            out.append(p)
    return out


def brute_orbits(g: ChainGraph, fixed=None):
    orbits = {}
    for p in brute_automorphisms(g):
        if fixed is not None and p[fixed] != fixed:
            continue
        for v in range(g.n):
            orbits.setdefault(v, set()).add(p[v])
    return {frozenset(o) for o in orbits.values()}


# -- mechanisms (inversions) -----------------------------------------------------------------------------------
def test_four_bar_has_one_inversion_and_one_crank():
    invs = inversions(FOUR_BAR)
    assert len(invs) == len(brute_orbits(FOUR_BAR)) == 1
    assert invs[0].name == "four-bar"
    cranks = driver_placements(invs[0])
    # the two links hinged to the frame are exchanged by the reflection that fixes the frame
    frame = invs[0].frame
    hinged = {v for e in FOUR_BAR.edges if frame in e for v in e if v != frame}
    orbits = [o for o in brute_orbits(FOUR_BAR, fixed=frame) if o & hinged]
    assert len(cranks) == len(orbits) == 1
    assert set(cranks[0].orbit) == hinged


def test_six_link_inversions_are_the_five_named_six_bars():
    names = {}
    for g in (WATT, STEPHENSON):
        invs = inversions(g)
        assert len(invs) == len(brute_orbits(g))
        for inv in invs:
            names[inv.name] = inv
    # Tsai (2001): 2 chains, 5 mechanisms of six links
    assert sorted(names) == ["Stephenson I", "Stephenson II", "Stephenson III", "Watt I", "Watt II"]
    # the names by graph properties: frame degree and the ternary links next to the frame
    for name, inv in names.items():
        g, f = inv.chain, inv.frame
        tern_next = sum(1 for e in g.edges if f in e for v in e if v != f and g.degrees[v] == 3)
        if name.endswith("III") or name == "Watt II":
            assert g.degrees[f] == 3
        elif name == "Stephenson I":
            assert g.degrees[f] == 2 and tern_next == 2
        else:
            assert g.degrees[f] == 2 and tern_next in (0, 1)
    # IDs: <chain id>/f<k>, distinct, and independent of the labelling the chain was given in
    ids = {inv.id for inv in names.values()}
    assert len(ids) == 5
    relabel = [5, 3, 0, 4, 1, 2]
    es = [(relabel[u], relabel[v]) for u, v in STEPHENSON.edges]
    for inv in inversions(STEPHENSON):
        assert inversion_at(6, es, relabel[inv.frame]).id == inv.id


def test_driver_placements_agree_with_brute_force():
    for g in (FOUR_BAR, WATT, STEPHENSON):
        for inv in inversions(g):
            f = inv.frame
            hinged = {v for e in g.edges if f in e for v in e if v != f}
            expected = {o for o in brute_orbits(g, fixed=f) if o & hinged}
            assert {frozenset(d.orbit) for d in driver_placements(inv)} == expected


@pytest.mark.parametrize("links, mechanisms", [(6, 5), (8, 71), pytest.param(10, 1834, marks=pytest.mark.slow)])
def test_mechanism_counts_of_the_literature(links, mechanisms):
    chains = pytest.importorskip("assur.structure.atlas.chains")
    # Tsai (2001), table of 1-DOF planar chains and mechanisms: 6 links 5, 8 links 71, 10 links 1834
    assert sum(len(inversions(c.graph)) for c in chains.chains(links, 1)) == mechanisms


# -- Baranov trusses and Assur groups --------------------------------------------------------------------------
def brute_trusses(n):
    """Every simple graph on n vertices with 3(n − 1)/2 edges tried (n ≤ 7): the definition checked directly."""
    j = 3 * (n - 1) // 2
    found = set()
    for es in itertools.combinations(itertools.combinations(range(n), 2), j):
        if is_baranov_truss(n, es):
            found.add(canonical(n, es)[0])
    return found


@pytest.mark.parametrize("n", [3, 5, pytest.param(7, marks=pytest.mark.slow)])
def test_trusses_equal_brute_force(n):
    assert {t.edges for t in baranov_trusses(n)} == brute_trusses(n)


@pytest.mark.parametrize("links, count", [(3, 1), (5, 1), (7, 3), (9, 28)])
def test_baranov_truss_counts_of_the_literature(links, count):
    # the Baranov-truss tables as cited (module docstring): 1, 1, 3, 28 trusses of 3, 5, 7, 9 links; each also
    # computed independently below (brute force, the chains plus a binary link, geng)
    trusses = baranov_trusses(links)
    assert len(trusses) == count
    for t in trusses:
        assert t.mobility == 0 and is_baranov_truss(t.n, t.edges)


@pytest.mark.parametrize("n, count", [(7, 3), (9, 28), (11, 562)])
def test_trusses_from_the_chains_plus_a_binary_link(n, count):
    """Every truss of n ≥ 5 links has a binary link (its mean degree 3(n − 1)/n is below 3) whose removal leaves a
    1-DOF chain of n − 1 links (mobility 3(n − 2) − 2(j − 2) = 1, its sub-chains are proper sub-chains of the
    truss): so the n-link trusses are the valid results of adding one binary link to the (n − 1)-link chains
    (230 of 10 links: OEIS A233288, Tsai). Both constructions give the same set: 562 for 11 links, not the
    tables' 633 (see the module docstring)."""
    chains = pytest.importorskip("assur.structure.atlas.chains")
    via_chains = set()
    for c in chains.chains(n - 1, 1):
        g = c.graph
        for u, v in itertools.combinations(range(g.n), 2):
            ce, _ = canonical(n, sorted(list(g.edges) + [(u, n - 1), (v, n - 1)]))
            if ce not in via_chains and is_baranov_truss(n, ce):
                via_chains.add(ce)
    assert {t.edges for t in baranov_trusses(n)} == via_chains
    assert len(via_chains) == count


GENG = shutil.which("nauty-geng") or shutil.which("geng")


@pytest.mark.skipif(GENG is None, reason="nauty's geng is not installed (Debian package nauty)")
@pytest.mark.parametrize("n, count", [(9, 28), (11, 562)])
def test_trusses_equal_exhaustive_enumeration(n, count):
    """nauty's geng lists every connected simple graph with n vertices, 3(n − 1)/2 edges and minimum degree 2
    once (27 678 for 11 links); the definition is checked here on all proper subsets with numpy."""
    out = subprocess.run([GENG, "-cq", "-d2", str(n), f"{3 * (n - 1) // 2}:{3 * (n - 1) // 2}"],
                         capture_output=True, encoding="utf-8", check=True).stdout.split()
    graphs = [nx.from_graph6_bytes(line.encode()) for line in out]
    subsets = np.arange(1 << n)
    bits = ((subsets[:, None] >> np.arange(n)) & 1).astype(np.uint8)
    size = bits.sum(axis=1).astype(np.int64)
    proper = (size >= 2) & (size < n)
    found = set()
    for start in range(0, len(graphs), 1000):
        block = graphs[start:start + 1000]
        us = np.array([[u for u, _ in g.edges] for g in block])
        vs = np.array([[v for _, v in g.edges] for g in block])
        inside = (bits[:, us] & bits[:, vs]).sum(axis=2, dtype=np.int64)
        ok = ((3 * (size[:, None] - 1) - 2 * inside >= 1) | ~proper[:, None]).all(axis=0)
        found |= {canonical(n, list(g.edges))[0] for g, good in zip(block, ok) if good}
    assert len(found) == count
    assert {t.edges for t in baranov_trusses(n)} == found


def test_assur_groups_of_two_and_four_links():
    dyad = assur_group_counts(2)
    assert dyad["groups"] == 1 and dyad["by_order"] == {2: 1} and dyad["by_class"] == {2: 1}
    four = assur_group_counts(4)
    # Artobolevsky: the triad (class III, order 3) and the four-link contour group (class IV, order 2)
    assert four["groups"] == 2 and four["by_order"] == {2: 1, 3: 1} and four["by_class"] == {3: 1, 4: 1}
    by = {(g.group_class, g.order) for g in assur_groups(4)}
    assert by == {(3, 3), (4, 2)}


def vf2_orbits(g: ChainGraph) -> set:
    """The link orbits of the automorphism group, by networkx's VF2 (no nauty)."""
    graph = nx.Graph(list(g.edges))
    orbits = {v: {v} for v in graph}
    for m in nx.algorithms.isomorphism.GraphMatcher(graph, graph).isomorphisms_iter():
        for v, w in m.items():
            orbits[v].add(w)
    return {frozenset(o) for o in orbits.values()}


@pytest.mark.parametrize("links, groups", [(2, 1), (4, 2), (6, 10), (8, 173)])
def test_group_counts_are_the_trusses_link_orbits(links, groups):
    counts = assur_group_counts(links)
    trusses = baranov_trusses(links + 1)
    assert counts["baranov_trusses"] == len(trusses)
    # the groups: one per orbit of links, computed here without nauty
    orbits = [(t, o) for t in trusses for o in (brute_orbits(t) if links <= 6 else vf2_orbits(t))]
    assert counts["groups"] == len(orbits) == groups
    # the order is the frame link's degree, the same on its whole orbit
    by_order: dict = {}
    for t, o in orbits:
        d = t.degrees[min(o)]
        by_order[d] = by_order.get(d, 0) + 1
    assert counts["by_order"] == by_order
    assert sum(counts["by_order"].values()) == sum(counts["by_class"].values()) == counts["groups"]
    for g in assur_groups(links):
        # order = outer pairs = the frame link's joints; W = 3·(links) − 2·(joints) = 0 once attached
        assert g.order == sum(1 for e in g.truss.edges if g.frame in e)
        assert 3 * g.links - 2 * g.joints == 0
        assert 2 <= g.group_class <= g.links


# -- type synthesis ---------------------------------------------------------------------------------------------
def test_dyad_kinds():
    kinds = dyad_kinds()
    assert kinds == ["RRR", "RRP", "RPR", "PRP", "PPR"]
    # independently: the 8 assignments (outer, inner, outer), up to swapping the outer pairs, without PPP
    classes = {min(a, a[::-1]) for a in itertools.product("RP", repeat=3)}
    assert len(kinds) == len(classes - {("P", "P", "P")})


def test_type_assignments_of_the_triad_exclude_prismatic_loops():
    truss = baranov_trusses(5)[0]
    frame = next(v for v in range(5) if truss.degrees[v] == 3)
    types = type_assignments(truss, frame)
    assert ("R",) * truss.joints in types
    for t in types:
        p_edges = [e for e, k in zip(truss.edges, t) if k == "P"]
        # no loop of prismatic pairs: the P edges form a forest
        assert len(p_edges) <= truss.n - 1
        parent = list(range(truss.n))

        def find(x):
            while parent[x] != x:
                x = parent[x]
            return x
        for u, v in p_edges:
            a, b = find(u), find(v)
            assert a != b
            parent[a] = b


# -- identification of the examples ------------------------------------------------------------------------------
def planar_examples():
    out = []
    for f in sorted(EXAMPLES.glob("*.toml")):
        doc = tomllib.loads(f.read_text(encoding="utf-8"))
        if doc.get("format", "assur/1") == "assur/1":
            out.append(f)
    return out


def load(name):
    import assur
    return assur.load(EXAMPLES / name)


@pytest.mark.parametrize("path", planar_examples(), ids=lambda p: p.name)
def test_every_example_is_identified_or_spatial(path):
    import assur
    m = assur.load(path)
    entry = identify(m)
    if m.dimension == 3:
        assert entry is None
        return
    assert entry is not None
    assert entry.dof == 3 * (entry.links - 1) - 2 * entry.joints
    assert entry.inversion_id.startswith(entry.chain_id + "/f")
    assert entry.line().startswith(f"atlas: {entry.chain_id} ")


def test_named_examples():
    # names against the files' own descriptions
    assert identify(load("watt2.toml")).name == "Watt II"                 # "A Watt II six-bar"
    assert identify(load("stephenson3.toml")).name == "Stephenson III"    # "A Stephenson III six-bar"
    assert identify(load("klann.toml")).name == "Stephenson III"          # "a modified Stephenson III chain"
    for f in ("crank_rocker.toml", "walker_fourbar.toml", "chebyshev_lambda.toml"):
        assert identify(load(f)).name == "four-bar"
    for f in ("slider_crank.toml", "walker_crank_slider.toml"):
        e = identify(load(f))
        assert e.name == "slider-crank" and e.chain_name == "four-bar" and e.prismatic == 1
    # paper 004's six-bar: crank plate and bent rocker (both ternary) hinged to a binary frame
    six = identify(load("walker_sixbar.toml"))
    assert six.chain_name == "Stephenson" and six.name == "Stephenson I" and six.dof == 1
    jansen = identify(load("jansen.toml"))
    assert jansen.links == 8 and jansen.joints == 10 and jansen.dof == 1
    klann = identify(load("klann.toml"))
    assert klann.links == 6 and klann.chain_name == "Stephenson"


def test_same_topology_same_chain():
    a, b = identify(load("walker_sixbar.toml")), identify(load("walker_sixbar_beta1_60.toml"))
    assert a.chain_id == b.chain_id and a.inversion_id == b.inversion_id
    s3, kl = identify(load("stephenson3.toml")), identify(load("klann.toml"))
    assert s3.chain_id == kl.chain_id and s3.inversion_id == kl.inversion_id
    assert identify(load("watt2.toml")).chain_id != s3.chain_id
    four = {identify(load(f)).inversion_id for f in ("crank_rocker.toml", "walker_fourbar.toml",
                                                     "chebyshev_lambda.toml", "slider_crank.toml")}
    assert len(four) == 1
    # and the chain IDs are those of the hand-built graphs
    assert identify(load("watt2.toml")).chain_id == WATT.id and s3.chain_id == STEPHENSON.id


def test_info_prints_the_atlas_line(capsys):
    from assur.cli.main import main
    assert main(["info", str(EXAMPLES / "watt2.toml")]) == 0
    out = capsys.readouterr().out
    entry = identify(load("watt2.toml"))
    assert f"atlas: {WATT.id} Watt II (frame: {entry.inversion_id})" in out
