"""A small dense linear solve written element-wise: Gaussian elimination with partial pivoting on a matrix given as
rows of entries — numbers, numpy arrays of a batch, or traced symbols (:mod:`.trace`) alike.

The compiled Newton kernels trace it (a branch on a traced value is refused, so a pivot chosen per sample is a
select, ``numpy.where``); on numpy arrays it solves every sample of a batch at once. What is known when the code runs
is decided then, so a traced matrix's structure costs nothing: an entry that is the number 0 is no work, a column
whose candidate pivots are all numbers (the ±1 of a body's x and y in loop equations) is pivoted on the largest
of them without a select, and such columns are eliminated first. The remaining columns are pivoted per sample on
the entry of largest magnitude (the first one on a tie), as LAPACK's partial pivoting does, so the growth of the
entries is bounded the same way; only the order of the columns and so the round-off differ from
``numpy.linalg.solve``.

:func:`factor` eliminates a matrix once; :meth:`Factors.solve` replays the elimination on right-hand sides (a Newton
step and the implicit-differentiation jets share one factorisation) and :attr:`Factors.det` is the determinant (0
where a column has no candidate pivot at all).
"""
from __future__ import annotations

import numpy as np


def _zero(x) -> bool:
    """True when ``x`` is the number 0 (known now: no work)."""
    return isinstance(x, (int, float, np.integer, np.floating)) and x == 0


def _number(x) -> bool:
    """True when ``x`` is a plain number (known now, so a pivot is chosen on it without a select)."""
    return isinstance(x, (int, float, np.integer, np.floating))


class _Step:
    """One elimination step: the column, the candidate rows (indices into the active rows, moved to the front), the
    select flags (``take[i]``: candidate i beats the ones before it; None when the pivot is known now) and the
    multipliers of the rows below the pivot."""
    __slots__ = ("col", "order", "chosen", "take", "mult", "inv")

    def __init__(self, col, order, chosen, take, mult, inv):
        self.col, self.order, self.chosen, self.take, self.mult, self.inv = col, order, chosen, take, mult, inv


class Factors:
    """The elimination of an n × n matrix: its steps and upper-triangular rows (col → entry), the determinant."""

    def __init__(self, n, steps, upper, det, singular):
        self.n, self.steps, self.upper, self.det, self.singular = n, steps, upper, det, singular

    def solve(self, b: list) -> list:
        """x with A·x = b for one right-hand side ``b`` (n entries); NaN where the matrix has a column without a
        candidate pivot."""
        if self.singular:
            return [np.nan] * self.n
        active = list(b)
        pivots = []
        for st in self.steps:
            active = [active[i] for i in st.order]
            m = len(st.mult) + 1
            if st.take is None:
                piv = active[st.chosen]
                rest = active[:st.chosen] + active[st.chosen + 1:m]
            else:
                piv, rest = _select(active[:m], st.take)
            rest = [r - l * piv if not _zero(l) else r for r, l in zip(rest, st.mult)]
            pivots.append(piv)
            active = rest + active[m:]
        x = [None] * self.n
        for st, piv, row in zip(reversed(self.steps), reversed(pivots), reversed(self.upper)):
            acc = piv
            for c, u in row.items():
                if c != st.col:
                    acc = acc - u * x[c]
            x[st.col] = acc * st.inv
        return x


def _select(cands, take):
    """The pivot (the candidate that wins the running comparison) and the other candidates, the winner's place
    taken by the first candidate (a swap): element-wise selects on ``take[i]`` (candidate i beats those before)."""
    m = len(cands)
    piv = cands[0]
    for i in range(1, m):
        piv = np.where(take[i], cands[i], piv)
    # candidate i is the winner when it beats those before and no later one beats it
    later = None
    rest = []
    for i in range(m - 1, 0, -1):
        won = take[i] if later is None else (take[i] & ~later)
        later = take[i] if later is None else (later | take[i])
        rest.append(np.where(won, cands[0], cands[i]))
    return piv, rest[::-1]


def _select_row(rows, take, cols):
    """:func:`_select` on whole rows (dicts col → entry) over ``cols``."""
    out_piv, out_rest = {}, [dict() for _ in rows[1:]]
    for c in cols:
        piv, rest = _select([r.get(c, 0.0) for r in rows], take)
        if not _zero(piv):
            out_piv[c] = piv
        for o, v in zip(out_rest, rest):
            if not _zero(v):
                o[c] = v
    return out_piv, out_rest


def factor(rows) -> Factors:
    """Gaussian elimination with partial pivoting of the square matrix ``rows`` (n lists of n entries: numbers,
    arrays or traced symbols). See the module's docstring for the order of the columns and the pivots."""
    n = len(rows)
    active = [{c: v for c, v in enumerate(r) if not _zero(v)} for r in rows]
    cols = list(range(n))
    steps, upper = [], []
    sign = 1.0
    det = 1.0
    for _ in range(n):
        # the next column: one whose candidate pivots are all numbers, else the first remaining one
        pick = None
        for c in cols:
            cands = [r[c] for r in active if c in r]
            if cands and all(_number(v) for v in cands):
                pick = c
                break
        col = cols[0] if pick is None else pick
        if (cols.index(col)) % 2:
            sign = -sign
        cols.remove(col)
        cand = [i for i, r in enumerate(active) if col in r]
        if not cand:
            return Factors(n, steps, upper, 0.0, True)
        # candidates to the front, in order (a permutation of the active rows: its sign)
        order = cand + [i for i in range(len(active)) if i not in cand]
        sign *= _permutation_sign(order)
        active = [active[i] for i in order]
        m = len(cand)
        entries = [active[i][col] for i in range(m)]
        remaining = set().union(*(active[i].keys() for i in range(m)))
        if all(_number(v) for v in entries):
            chosen = max(range(m), key=lambda i: (abs(entries[i]), -i))
            if chosen:
                sign = -sign if chosen % 2 else sign
            piv = active[chosen]
            rest = active[:chosen] + active[chosen + 1:m]
            take = None
        else:
            take = [None]
            best = abs(entries[0])
            for v in entries[1:]:
                t = np.abs(v) > best
                take.append(t)
                best = np.where(t, np.abs(v), best)
            piv, rest = _select_row(active[:m], take, sorted(remaining))
            chosen = None
            # the winner swaps with the first candidate: one transposition unless the first one wins
            first_wins = None
            for t in take[1:]:
                first_wins = ~t if first_wins is None else (first_wins & ~t)
            sign = sign * np.where(first_wins, 1.0, -1.0) if m > 1 else sign
        p = piv[col]
        inv = 1.0 / p
        det = det * p
        mult = []
        new_rest = []
        for r in rest:
            l = r[col] * inv
            mult.append(l)
            nr = {}
            for c in set(r) | set(piv):
                if c == col:
                    continue
                v = r.get(c, 0.0)
                pc = piv.get(c, 0.0)
                v = v - l * pc if not (_zero(pc) or _zero(l)) else v
                if not _zero(v):
                    nr[c] = v
            new_rest.append(nr)
        steps.append(_Step(col, order, chosen, take, mult, inv))
        upper.append(piv)
        active = new_rest + active[m:]
    return Factors(n, steps, upper, det * sign, False)


def _permutation_sign(order) -> float:
    """+1 or −1: the sign of a permutation given as a list of indices."""
    seen = [False] * len(order)
    sign = 1.0
    for i in range(len(order)):
        if seen[i]:
            continue
        j, length = i, 0
        while not seen[j]:
            seen[j] = True
            j = order[j]
            length += 1
        if length % 2 == 0:
            sign = -sign
    return sign
