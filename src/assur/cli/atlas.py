"""``assur atlas``: the atlas of planar kinematic chains (docs/atlas.md); the command-line face of
:mod:`assur.structure.atlas` (the mathematics) and :mod:`assur.io.atlas` (the entries as files).

``assur atlas --links N --dof F`` prints how many chains of N links and mobility F there are (planar ones, their
mechanisms, by link assortment; the chains themselves when there are few); ``--json`` prints one JSON object;
``-o DIR`` writes the whole list as ``DIR/atlas.json`` (format ``assur-atlas/1``, the same bytes on every run)
and, for 1-DOF chains of at most :data:`MECHANISM_LINKS` links, each inversion as a mechanism file and an SVG
drawing (docs/atlas.md, "Each entry as a mechanism"). ``assur atlas --assur-groups --links N`` counts the Assur
groups of N links. ``assur atlas --walking-legs --links 6|8`` ranks the walking legs by their gait
(:mod:`assur.cli.legs`).
"""
from __future__ import annotations

import argparse

from .args import path_arg

#: the version tag of the atlas JSON file
ATLAS_FORMAT = "assur-atlas/1"


def _int(text):
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer: {text!r}") from None


def register(sub) -> None:
    """Add ``atlas`` to the argparse sub-parsers ``sub``."""
    help_ = "structural synthesis: the atlas of planar kinematic chains (counts, canonical IDs) and Assur groups"
    sp = sub.add_parser("atlas", help=help_, description=(
        "Enumerate the planar kinematic chains of revolute pairs with N links and mobility F, each once: "
        "connected, no cut link, no rigid sub-chain (every set of links keeps a mobility of at least 1), "
        "isomorphs removed by canonical labelling, non-planar chains kept and flagged. With -o, 1-DOF "
        "chains of at most 8 links also get each mechanism as a file that assembles and an SVG drawing."))
    sp.add_argument("--links", type=_int, required=True, metavar="N", help="number of links")
    sp.add_argument("--dof", type=_int, default=None, metavar="F", help="mobility of the chains (e.g. 1)")
    sp.add_argument("--assur-groups", action="store_true",
                    help="count the Assur groups of N links instead (by order and class)")
    sp.add_argument("--walking-legs", action="store_true",
                    help="rank the 1-DOF walking legs of 6 or 8 links (a crank at the frame, a foot on each link) by "
                         "a short gait synthesis of each; -o DIR writes the report page and the mechanism files")
    sp.add_argument("--json", action="store_true", help="print one JSON object")
    sp.add_argument("-o", "--output", type=path_arg, default=None, metavar="DIR",
                    help="write the atlas as DIR/atlas.json (format assur-atlas/1) and, for 1-DOF chains of at most "
                         "8 links, each mechanism's file DIR/<id>.toml and drawing DIR/<id>.svg (8 links: a few minutes, the engine assembles each one)")
    from .legs import add_arguments
    add_arguments(sp)
    sp.set_defaults(func=cmd_atlas)


def _bad(option: str, message: str):
    from ..errors import SpecError
    return SpecError([(option, message)])


def cmd_atlas(args) -> int:
    """``assur atlas ...``."""
    if args.walking_legs:
        if args.assur_groups:
            raise _bad("--walking-legs", "give either --walking-legs or --assur-groups")
        from .legs import cmd_walking_legs
        return cmd_walking_legs(args)
    for option in ("budget", "starts", "seed", "limit", "workers", "dask", "triads", "rank", "window_budget",
                   "clearance"):
        if getattr(args, option) not in (None, False):
            raise _bad(f"--{option.replace('_', '-')}", "only with --walking-legs")
    if args.assur_groups:
        return _groups(args)
    if args.dof is None:
        raise _bad("--dof", "give the mobility of the chains (e.g. --dof 1)")
    from ..structure.atlas.chains import chains, check_size, count
    if args.links < 4:
        raise _bad("--links", f"a closed chain of revolute pairs needs at least 4 links: {args.links}")
    if args.dof < 1:
        raise _bad("--dof", f"the mobility must be at least 1: {args.dof}")
    try:
        check_size(args.links, args.dof)
    except ValueError as exc:
        raise _bad("--links" if "too large" in str(exc) else "--dof", str(exc)) from None
    if args.output is not None:            # an output it may not write is refused before the minutes of work
        from ..io.output import check_output_directory
        check_output_directory(args.output)
    summary = count(args.links, args.dof)
    entries = chains(args.links, args.dof)
    if args.output is not None:
        _write(args.output, args.links, args.dof, summary, entries)
    if args.json:
        from ..io.output import json_text
        print(json_text(summary))
        return 0
    _print(summary, entries)
    if args.output is not None:
        print(f"wrote {args.output}/atlas.json")
    return 0


def atlas_document(links: int, dof: int, summary: dict, entries) -> dict:
    """The ``assur-atlas/1`` document of a chain atlas."""
    return {"format": ATLAS_FORMAT, "links": links, "dof": dof, "joints": summary["joints"],
            "counts": {k: summary[k] for k in ("chains", "planar_chains", "mechanisms")},
            "chains": [e.as_dict() for e in entries]}


#: the largest 1-DOF chains whose mechanisms ``-o`` writes as mechanism files and drawings (8 links: about two
#: minutes; 10 links would take about an hour)
MECHANISM_LINKS = 8


#: the mechanisms computed in this process, by inversion ID (a second ``-o`` of the same atlas reuses them)
_MECHANISMS: dict = {}


def mechanism_files(entries) -> tuple[list[dict], dict[str, str]]:
    """(one row per inversion, {file name: text}): the mechanism file ``<stem>.toml`` and drawing ``<stem>.svg``
    of each inversion of ``entries`` with its first crank placement (docs/atlas.md, "Each entry as a
    mechanism")."""
    from ..io.atlas import mechanism_entry, svg
    from ..io.toml_writer import dumps
    from ..structure.assur import analyse, roman
    from ..structure.atlas.mechanisms import inversions
    rows, files = [], {}
    for e in entries:
        for inv in inversions(e.graph):
            m = _MECHANISMS.get(inv.id)
            if m is None:
                m = _MECHANISMS[inv.id] = mechanism_entry(inv)
            s = analyse(m.mechanism)
            stem = m.name
            files[f"{stem}.toml"] = dumps(m.document)
            files[f"{stem}.svg"] = svg(m.sketch, m.document["name"])
            rows.append({"inversion": inv.id, "chain": e.id, "name": inv.name, "frame": inv.frame,
                         "crank": m.sketch.crank, "file": f"{stem}.toml", "drawing": f"{stem}.svg",
                         "structural_formula": s.structural_formula,
                         "group_classes": [roman(g.group_class) for g in s.groups],
                         "assembles": m.assembles, "full_turn": m.full_turn, "turn": round(m.turn, 4),
                         "sketch_attempt": m.sketch.attempt})
    return rows, files


def _write(out_dir, links, dof, summary, entries) -> None:
    import json

    from ..io.output import atomic_directory
    doc = atlas_document(links, dof, summary, entries)
    rows = [json.dumps(c, ensure_ascii=False) for c in doc.pop("chains")]
    mech_rows, files = ([], {})
    if dof == 1 and links <= MECHANISM_LINKS:
        mech_rows, files = mechanism_files(entries)
    head = json.dumps(doc, ensure_ascii=False, indent=1)[:-2]      # without the closing "\n}"
    text = head + ',\n "chains": [\n  ' + ",\n  ".join(rows) + "\n ]"   # one chain per line
    if mech_rows:
        text += ',\n "mechanisms": [\n  ' + ",\n  ".join(json.dumps(r, ensure_ascii=False) for r in mech_rows) + "\n ]"
    text += "\n}\n"
    with atomic_directory(out_dir) as tmp:
        (tmp / "atlas.json").write_text(text, encoding="utf-8")
        for name, body in files.items():
            (tmp / name).write_text(body, encoding="utf-8")


def _print(summary: dict, entries) -> None:
    n, f = summary["links"], summary["dof"]
    print(f"{n}-link chains of mobility {f} ({summary['joints']} revolute joints): {summary['chains']} chains "
          f"({summary['planar_chains']} planar), {summary['mechanisms']} mechanisms (frame choices)")
    cut = summary.get("chains_with_cut_links", 0)
    if cut:
        print(f"not counted: {cut} non-degenerate chains with a cut link (fractionated)")
    width = max((len(k) for k in summary["by_assortment"]), default=10)
    print(f"  {'assortment':<{max(width, 10)}}  chains   (binary, ternary, quaternary, ... links)")
    for key, c in summary["by_assortment"].items():
        print(f"  {key:<{max(width, 10)}}  {c:>6}")
    if len(entries) <= 40:
        for e in entries:
            print(f"  {e.id}  [{','.join(map(str, e.assortment))}]  {'planar' if e.planar else 'non-planar'}  "
                  f"{e.edge_text}")


def _groups(args) -> int:
    if args.dof is not None:
        raise _bad("--dof", "Assur groups have mobility 0: leave out --dof with --assur-groups")
    if args.output is not None:
        raise _bad("--output", "-o is not available with --assur-groups yet")
    if args.links < 2:
        raise _bad("--links", f"an Assur group has at least 2 links: {args.links}")
    try:
        from ..structure.atlas.groups import assur_group_counts
    except ModuleNotFoundError as exc:
        if exc.name and exc.name.endswith("structure.atlas.groups"):
            raise _bad("--assur-groups", "the Assur-group atlas is not available in this version") from None
        raise
    try:
        result = assur_group_counts(args.links)
    except ValueError as exc:
        raise _bad("--links", str(exc)) from None
    if args.json:
        from ..io.output import json_text
        print(json_text(result))
        return 0
    print(f"Assur groups of {args.links} links: {result['groups']}")
    for order, c in sorted(result.get("by_order", {}).items(), key=lambda kv: int(kv[0])):
        print(f"  order {order}: {c}")
    for cls, c in result.get("by_class", {}).items():
        print(f"  class {cls}: {c}")
    return 0
