"""The atlas of planar kinematic chains (assur.structure.atlas.chains) and ``assur atlas``.

Conditions (docs/atlas.md): simple graph, connected, mobility 3(n − 1) − 2j = F, no cut link (2-connected), no
sub-chain of ≥ 2 links with mobility ≤ 0. Every count is checked against a literature number where one was
found (sources below and in the comments), and every output chain by tests written here from first principles
(all link subsets by itertools or numpy, networkx for connectivity, nauty's geng for all graphs), not by the
enumeration's own tests.

Literature (the counts below), each with what it counts:

* [OEIS] OEIS A233288, "Number of (3/2,2)-tight graphs with 2n vertices, or kinematic chains with 2n links"
  (D. Eppstein 2013; https://oeis.org/A233288): 1, 1, 2, 16, 230, 6856, 318162, 19819281 for 2, 4, …, 16
  links. Its comment defines the chains as here: 1 DOF, every joint pins two links, no rigid sub-system. (It also
  notes that Sunkari & Schmidt's paper has a typo for 14 links.)
* [Tsai] L.-W. Tsai, *Mechanism Design: Enumeration of Kinematic Structures According to Function*, CRC Press,
  2001, ch. 4 (number of planar 1-DOF chains of revolute pairs: 4 links 1, 6 links 2 (Watt, Stephenson),
  8 links 16, 10 links 230, 12 links 6 856; and by link assortment).
* [AME] "Automatic topological structural synthesis algorithm of planar simple joint kinematic chains",
  *Advances in Mechanical Engineering* (2016), doi:10.1177/1687814016638055
  (https://sage.cnpereading.com/doi/10.1177/1687814016638055), introduction: by Franke's notation (Davies &
  Crossley; Soni) "40 types of 9-link 2-degree of freedom (2-DOF) and 230 types of 10-link 1-DOF planar simple
  joint kinematic chains" were synthesized. Here 9 links, 2 DOF gives 35 chains without a cut link and 5 with
  one, so that 40 is the total including the fractionated chains (the count without them is 35).
* [Tuttle] E. R. Tuttle, "Generation of planar kinematic chains", *Mechanism and Machine Theory* 31 (1996)
  729–748 (abstract: https://c.coek.info/pdf-generation-of-planar-kinematic-chains-.html): its tables count the
  *non-fractionated* chains only (2–6 loops, 1–3 DOF), i.e. the ``chains`` column here, not the totals. Its
  table values were not readable for these tests.
* [SS] P. Sunkari, L. C. Schmidt, "Structural synthesis of planar kinematic chains by adapting a Mckay-type
  algorithm", *Mechanism and Machine Theory* 41 (2006) 1021–1030, and [HH] W.-M. Hwang, Y.-W. Hwang,
  "Computer-aided structural synthesis of planar kinematic chains with simple joints", *Mechanism and Machine
  Theory* 27 (1992) 189–199: multi-DOF tables, not read for these tests.

The 1-DOF chain counts agree in every source (for 1 DOF no chain with a cut link can be non-degenerate: its two
sides' mobilities add up to 1, so one side would be rigid). For 2 and 3 DOF the sources differ in what they
count: totals with the fractionated chains (chains with a cut link, [AME]) and totals without them ([Tuttle]).
Only the 9-link 2-DOF total (40, [AME]) was verified against a printed source; every other multi-DOF number
below is marked "(no literature table read)" and is checked instead, chain for chain, by an exhaustive
enumeration of all graphs (nauty's ``geng``, when installed: test_chains_equal_exhaustive_enumeration).
"""
from __future__ import annotations

import itertools
import json
import random
import shutil
import subprocess

import networkx as nx
import numpy as np
import pytest

from assur.cli.main import main
from assur.structure.atlas.chains import chains, count, is_degenerate
from assur.structure.atlas.graphs import ChainGraph


# ---------------------------------------------------------------------------------------------------------------
# Independent checks written here (no code of the enumeration)

def brute_force_rigid(n: int, edges) -> bool:
    """True when some set of ≥ 2 links has mobility 3(k − 1) − 2e ≤ 0: every subset by itertools."""
    for k in range(2, n + 1):
        for subset in itertools.combinations(range(n), k):
            s = set(subset)
            e = sum(1 for u, v in edges if u in s and v in s)
            if 3 * (k - 1) - 2 * e <= 0:
                return True
    return False


def assert_valid_chain(n: int, dof: int, edges) -> None:
    g = nx.Graph(list(edges))
    assert g.number_of_nodes() == n and g.number_of_edges() == len(edges)          # simple, every link used
    assert 3 * (n - 1) - 2 * len(edges) == dof
    assert min(d for _, d in g.degree) >= 2
    assert nx.is_biconnected(g)                                                      # no cut link
    assert not brute_force_rigid(n, edges)


# ---------------------------------------------------------------------------------------------------------------
# Counts against the literature

@pytest.mark.parametrize("links, expected", [
    (4, 1),      # the four-bar [OEIS], [Tsai]
    (6, 2),      # Watt and Stephenson [OEIS], [Tsai]
    (8, 16),     # [OEIS], [Tsai]
    (10, 230),   # [OEIS], [Tsai], [AME] (219 of them planar: see the planarity test)
    pytest.param(12, 6856, marks=pytest.mark.slow),   # [OEIS], [Tsai]
])
def test_one_dof_chain_counts(links, expected):
    assert count(links, 1)["chains"] == expected


@pytest.mark.parametrize("links, expected", [
    (6, 5),      # the five six-bar mechanisms: Watt I, II, Stephenson I, II, III (every textbook; [Tsai])
    (8, 71),     # eight-link 1-DOF mechanisms [Tsai]
    (10, 1834),  # ten-link 1-DOF mechanisms [Tsai]
])
def test_one_dof_mechanism_counts(links, expected):
    """Mechanisms = frame choices up to the chain's symmetry (the automorphism orbits of its links)."""
    assert count(links, 1)["mechanisms"] == expected


def test_one_dof_link_assortments():
    # [Tsai], ch. 4: 8 links: 9 (4 binary, 4 ternary), 5 (5, 2, 1 quaternary), 2 (6, 0, 2);
    # 10 links: 50 + 95 + 57 + 15 + 3 + 8 + 2 = 230
    assert count(8, 1)["by_assortment"] == {"4,4": 9, "5,2,1": 5, "6,0,2": 2}
    assert count(10, 1)["by_assortment"] == {"4,6": 50, "5,4,1": 95, "6,2,2": 57, "6,3,0,1": 15, "7,0,3": 3,
                                             "7,1,1,1": 8, "8,0,0,2": 2}


@pytest.mark.parametrize("links, dof, without_cut, with_cut", [
    (5, 2, 1, 0),       # the five-bar (a single loop: 3·4 − 2·5 = 2)
    (7, 2, 3, 1),       # 3 + 1 fractionated (two four-bars sharing a quaternary link); also by brute force below
    (9, 2, 35, 5),      # 35 + 5 = 40 = [AME]'s 40 nine-link 2-DOF chains (its total includes the fractionated)
    (11, 2, 753, 86),   # 753 + 86 = 839 (no literature table read: exhaustive enumeration below)
    (6, 3, 1, 0),       # the six-bar loop (3·5 − 2·6 = 3)
    (8, 3, 5, 2),       # 5 + 2 = 7 (no literature table read: exhaustive enumeration below)
    (10, 3, 74, 24),    # 74 + 24 = 98 (no literature table read: exhaustive enumeration below)
])
def test_multi_dof_chain_counts(links, dof, without_cut, with_cut):
    c = count(links, dof)
    assert (c["chains"], c["chains_with_cut_links"]) == (without_cut, with_cut)


def test_seven_link_two_dof_fractionated_chain_by_hand():
    """The one fractionated 7-link 2-DOF chain: two four-bar loops sharing one (quaternary) link."""
    shared = ChainGraph.of(7, [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (4, 5), (5, 6), (6, 0)])
    frac = [e for e in chains(7, 2, cut_links=True) if e.cut_link]
    assert [e.id for e in frac] == [shared.id]
    assert shared.id not in {e.id for e in chains(7, 2)}


# ---------------------------------------------------------------------------------------------------------------
# Completeness by an exhaustive enumeration of all graphs with nauty's geng (a different program: every connected
# simple graph with n vertices, j edges and minimum degree 2, once up to isomorphism), filtered by an all-subsets
# mobility test written here with numpy. Skipped where geng is not installed (Debian package "nauty").

GENG = shutil.which("nauty-geng") or shutil.which("geng")
needs_geng = pytest.mark.skipif(GENG is None, reason="nauty's geng is not installed (Debian package nauty)")


def geng_graphs(n: int, j: int) -> list:
    out = subprocess.run([GENG, "-cq", "-d2", str(n), f"{j}:{j}"], capture_output=True, encoding="utf-8", check=True)
    return [nx.from_graph6_bytes(line.encode()) for line in out.stdout.split()]


def without_rigid_subset(n: int, graphs, proper: bool = False) -> list[bool]:
    """For each graph: no set S of ≥ 2 links (< n with ``proper``) has 3(|S| − 1) − 2e(S) ≤ 0."""
    subsets = np.arange(1 << n)
    bits = ((subsets[:, None] >> np.arange(n)) & 1).astype(np.uint8)            # (2**n, n)
    size = bits.sum(axis=1).astype(np.int64)
    checked = (size >= 2) & ((size < n) if proper else True)
    result = []
    for start in range(0, len(graphs), 1000):
        block = graphs[start:start + 1000]
        us = np.array([[u for u, _ in g.edges] for g in block])
        vs = np.array([[v for _, v in g.edges] for g in block])
        inside = (bits[:, us] & bits[:, vs]).sum(axis=2, dtype=np.int64)           # (2**n, graphs): e(S)
        ok = (3 * (size[:, None] - 1) - 2 * inside >= 1) | ~checked[:, None]
        result.extend(ok.all(axis=0).tolist())
    return result


@needs_geng
@pytest.mark.parametrize("links, dof", [(10, 1), (9, 2), (11, 2), (8, 3), (10, 3)])
def test_chains_equal_exhaustive_enumeration(links, dof):
    graphs = geng_graphs(links, (3 * (links - 1) - dof) // 2)
    good = [g for g, ok in zip(graphs, without_rigid_subset(links, graphs)) if ok]
    whole = {ChainGraph.of(links, list(g.edges)).id for g in good if nx.is_biconnected(g)}
    fractionated = {ChainGraph.of(links, list(g.edges)).id for g in good if not nx.is_biconnected(g)}
    entries = chains(links, dof, cut_links=True)
    assert {e.id for e in entries if not e.cut_link} == whole
    assert {e.id for e in entries if e.cut_link} == fractionated
    if (links, dof) == (9, 2):
        assert len(whole) + len(fractionated) == 40                  # [AME]: 40 nine-link 2-DOF chains in all
    # the mechanisms (link orbits, by networkx's VF2 here, not nauty) and the planar chains of docs/atlas.md
    blocks = [g for g in good if nx.is_biconnected(g)]
    orbits = 0
    for g in blocks:
        orbit = {v: {v} for v in g}
        for m in nx.algorithms.isomorphism.GraphMatcher(g, g).isomorphisms_iter():
            for v, w in m.items():
                orbit[v].add(w)
        orbits += len({frozenset(o) for o in orbit.values()})
    c = count(links, dof)
    assert c["mechanisms"] == orbits
    assert c["planar_chains"] == sum(nx.check_planarity(g)[0] for g in blocks)


# ---------------------------------------------------------------------------------------------------------------
# Completeness by brute force over all graphs (independent of the contracted-graph method)

@pytest.mark.parametrize("links, dof", [(6, 1), (7, 2)])
def test_enumeration_equals_brute_force(links, dof):
    import pynauty
    j = (3 * (links - 1) - dof) // 2
    pairs = list(itertools.combinations(range(links), 2))
    found: dict[bytes, tuple] = {}
    for edges in itertools.combinations(pairs, j):
        deg = [0] * links
        for u, v in edges:
            deg[u] += 1
            deg[v] += 1
        if min(deg) < 2:
            continue
        g = nx.Graph(list(edges))
        if not nx.is_biconnected(g) or brute_force_rigid(links, edges):
            continue
        adj = {k: [v for u, v in edges if u == k] for k in range(links)}
        found.setdefault(pynauty.certificate(pynauty.Graph(links, adjacency_dict=adj)), edges)
    expected = {ChainGraph.of(links, e).id for e in found.values()}
    assert {e.id for e in chains(links, dof)} == expected


# ---------------------------------------------------------------------------------------------------------------
# Degeneracy

TRIANGLE_CHAIN = (6, [(0, 1), (1, 2), (2, 0), (2, 3), (3, 4), (4, 5), (5, 1)])
# the five-link Baranov truss (ternary links A = 0, B = 1; binary 2, 3, 4 each hinged to A and B: 3·4 − 2·6 = 0)
# moved as one body in a four-bar loop with the links 5, 6, 7: 8 links, 10 joints, mobility 1, no triangle
TRUSS_CHAIN = (8, [(0, 2), (2, 1), (0, 3), (3, 1), (0, 4), (4, 1), (2, 5), (5, 6), (6, 7), (7, 3)])


@pytest.mark.parametrize("chain", [TRIANGLE_CHAIN, TRUSS_CHAIN], ids=["triangle", "rigid-five-link"])
def test_degenerate_chains_are_caught_and_never_listed(chain):
    n, edges = chain
    assert 3 * (n - 1) - 2 * len(edges) == 1
    assert brute_force_rigid(n, edges)              # the independent check agrees that it is degenerate
    assert is_degenerate(n, edges, 1)
    assert ChainGraph.of(n, edges).id not in {e.id for e in chains(n, 1)}


def test_rigid_five_link_truss_has_no_triangle():
    """A triangle test alone would pass this chain: it has no three mutually hinged links."""
    n, edges = TRUSS_CHAIN
    assert sum(nx.triangles(nx.Graph(edges)).values()) == 0
    assert is_degenerate(n, edges)


def test_degeneracy_agrees_with_brute_force_on_random_graphs():
    rng = random.Random(7)
    pairs = list(itertools.combinations(range(8), 2))
    for _ in range(200):
        edges = rng.sample(pairs, 10)
        assert is_degenerate(8, edges) == brute_force_rigid(8, edges)


def test_is_degenerate_checks_the_mobility():
    with pytest.raises(ValueError):
        is_degenerate(*TRIANGLE_CHAIN, 2)


@pytest.mark.parametrize("links, dof", [(8, 1), (10, 1), (9, 2), (8, 3)])
def test_every_listed_chain_is_valid(links, dof):
    for e in chains(links, dof):
        assert_valid_chain(links, dof, e.edges)


def test_fractionated_chains_are_valid_and_have_a_cut_link():
    for e in chains(10, 3, cut_links=True):
        g = nx.Graph(list(e.edges))
        assert nx.is_connected(g) and not brute_force_rigid(10, e.edges)
        assert e.cut_link == (not nx.is_biconnected(g))


# ---------------------------------------------------------------------------------------------------------------
# Isomorph-free, stable IDs

def test_ids_distinct_and_invariant_under_relabelling():
    entries = chains(10, 1)
    ids = [e.id for e in entries]
    assert len(set(ids)) == len(ids)
    rng = random.Random(2026)
    for e in entries:
        perm = list(range(e.n))
        rng.shuffle(perm)
        relabelled = [(perm[u], perm[v]) for u, v in e.edges]
        rng.shuffle(relabelled)
        assert ChainGraph.of(e.n, relabelled).id == e.id
    # no two listed chains are isomorphic (networkx's own test, pairwise within each assortment)
    by: dict = {}
    for e in entries:
        by.setdefault(e.assortment, []).append(nx.Graph(list(e.edges)))
    for graphs in by.values():
        for a, b in itertools.combinations(graphs, 2):
            assert not nx.faster_could_be_isomorphic(a, b) or not nx.is_isomorphic(a, b)


def test_order_is_stable():
    """Sorted by link assortment, then canonical edge list: the same list on every call."""
    entries = chains(8, 1)
    keys = [(e.assortment, e.edges) for e in entries]
    assert keys == sorted(keys)
    assert [e.as_dict() for e in entries] == [e.as_dict() for e in chains(8, 1)]


# ---------------------------------------------------------------------------------------------------------------
# Planarity: each flag is checked by a certificate (an embedding with Euler's count of faces, or a Kuratowski
# subgraph reduced to K5 or K3,3 here)

def _euler_ok(g, embedding) -> bool:
    seen, faces = set(), 0
    for u, v in embedding.edges:
        if (u, v) not in seen:
            face = embedding.traverse_face(u, v, mark_half_edges=seen)
            faces += 1 if face else 0
    return g.number_of_nodes() - g.number_of_edges() + faces == 2


def _is_kuratowski(sub) -> bool:
    h = nx.Graph(sub)
    while True:
        two = [v for v in h if h.degree(v) == 2]
        if not two:
            break
        v = two[0]
        a, b = list(h.neighbors(v))
        h.remove_node(v)
        h.add_edge(a, b)
    return nx.is_isomorphic(h, nx.complete_graph(5)) or nx.is_isomorphic(h, nx.complete_bipartite_graph(3, 3))


def test_planarity_flags_have_certificates():
    entries = chains(10, 1)
    for e in entries:
        g = nx.Graph(list(e.edges))
        planar, cert = nx.check_planarity(g, counterexample=True)
        assert planar == e.planar
        assert _euler_ok(g, cert) if planar else _is_kuratowski(cert)
    # 10 links: 219 planar of 230 (every flag checked above by its certificate; Pyslvs is reported to list 223
    # planar ten-link chains, its triangle-only degeneracy test missing rigid five-link sub-chains)
    assert count(10, 1)["planar_chains"] == sum(e.planar for e in entries) == 219
    assert all(e.planar for e in chains(8, 1))


# ---------------------------------------------------------------------------------------------------------------
# The command

def test_cli_json(capsys):
    assert main(["atlas", "--links", "10", "--dof", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    entries = chains(10, 1)
    assert out["chains"] == len(entries) == 230
    assert out["planar_chains"] == sum(e.planar for e in entries)
    assert out["mechanisms"] == sum(len(set(e.orbits)) for e in entries)
    assert out["joints"] == 13 and out["links"] == 10 and out["dof"] == 1
    assert all(isinstance(out[k], int) for k in ("chains", "planar_chains", "mechanisms"))
    assert sum(out["by_assortment"].values()) == 230


def test_cli_text(capsys):
    assert main(["atlas", "--links", "6", "--dof", "1"]) == 0
    out = capsys.readouterr().out
    assert "2 chains" in out and "5 mechanisms" in out
    assert all(e.id in out for e in chains(6, 1))


def test_cli_output_is_reproducible(tmp_path, capsys):
    # 10 links: the atlas file alone (mechanism files are written up to 8 links; tests/test_atlas_layout.py)
    a, b = tmp_path / "a", tmp_path / "b"
    assert main(["atlas", "--links", "10", "--dof", "1", "-o", str(a)]) == 0
    assert main(["atlas", "--links", "10", "--dof", "1", "-o", str(b)]) == 0
    first = (a / "atlas.json").read_bytes()
    assert first == (b / "atlas.json").read_bytes()
    assert main(["atlas", "--links", "10", "--dof", "1", "-o", str(a)]) == 0      # a later run replaces it
    assert (a / "atlas.json").read_bytes() == first
    doc = json.loads(first)
    assert doc["format"] == "assur-atlas/1" and (doc["links"], doc["dof"]) == (10, 1)
    assert [c["id"] for c in doc["chains"]] == [e.id for e in chains(10, 1)]
    for c in doc["chains"]:
        head, body = c["edges"].split(":")
        edges = [tuple(map(int, p.split("-"))) for p in body.split(",")]
        assert int(head) == 10 and ChainGraph.of(10, edges).id == c["id"]
        assert_valid_chain(10, 1, edges)


@pytest.mark.parametrize("argv", [
    ["--links", "1", "--dof", "1"],
    ["--links", "3", "--dof", "1"],
    ["--links", "7", "--dof", "1"],      # 3·6 − 1 = 17 joints·2: not a whole number of joints
    ["--links", "16", "--dof", "1"],     # too large to finish
    ["--links", "6", "--dof", "0"],
    ["--links", "6"],                    # no --dof
    ["--links", "7", "--dof", "1", "--walking-legs"],
])
def test_cli_bad_input_one_line(argv, capsys):
    assert main(["atlas", *argv]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ")


def test_cli_output_refuses_a_user_directory(tmp_path, capsys):
    (tmp_path / "keep.txt").write_text("mine")
    assert main(["atlas", "--links", "6", "--dof", "1", "-o", str(tmp_path)]) == 1
    assert (tmp_path / "keep.txt").read_text() == "mine"
    assert capsys.readouterr().err.startswith("error: ")


def test_cli_usage_errors_exit_2(capsys):
    assert main(["atlas", "--links", "x", "--dof", "1"]) == 2
    assert main(["atlas", "--dof", "1"]) == 2
