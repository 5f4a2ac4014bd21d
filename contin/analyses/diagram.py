"""Bifurcation diagrams as ``networkx`` graphs.

Nodes are the end points and special points of branches; points that coincide (same parameter and
state within a tolerance) are one node, so a branch traced twice or a jump that lands where another
branch starts joins the pieces.  Edges are branch segments between consecutive nodes (with their
stability) and jumps.  A loading-unloading hysteresis loop therefore shows up as a directed cycle.
The plots that read branches and jumps are in :mod:`contin.plot.branches`.

With ``merge=True`` the graph is one of curves rather than of runs: a node of one branch that lies
inside another (between two of its stored points, on the curve through them) splits that branch
there, and a segment that runs along a segment already in the graph (either way) is merged into it
instead of added again.  Whether a point lies on a branch is decided by :func:`position_on`: the
branch between stored points is the cubic through four neighbouring ones.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..results.branch import Branch, BranchFileError
from ..results.io import json_ready, read_bundle, write_bundle
from .jump import JumpResult

if TYPE_CHECKING:  # networkx is imported lazily: it costs a noticeable part of import time
    import networkx as nx

__all__ = ["diagram", "hysteresis_cycles", "save_diagram", "load_diagram", "position_on", "point_at"]

#: Default tolerance of :func:`position_on` (scaled like node matching: relative to ``max(1, |x|)``).
CURVE_TOL = 1e-4
#: Samples per stored step where the cubic through the neighbouring points is searched.
_SAMPLES = 33


class NodeIndex:
    """The nodes of a diagram by parameter and state: points within ``rtol`` of each other are one node."""

    def __init__(self, rtol: float) -> None:
        self.rtol = rtol
        self.nodes: list[tuple[str, float, np.ndarray]] = []

    def find(self, p: float, u: np.ndarray) -> str | None:
        """The node at ``(p, u)``, or None."""
        for name, q, v in self.nodes:
            scale = max(1.0, float(np.max(np.abs(v), initial=0.0)))
            if abs(p - q) <= self.rtol * max(1.0, abs(p)) and v.shape == u.shape and \
                    float(np.max(np.abs(u - v), initial=0.0)) <= self.rtol * scale:
                return name
        return None

    def find_or_add(self, G: "nx.MultiDiGraph", kind: str, p: float, u: np.ndarray, **attrs: Any) -> str:
        """The node at ``(p, u)`` (``kind`` added to its kinds), or a new one."""
        name = self.find(p, np.asarray(u))
        if name is not None:
            kinds = G.nodes[name]["kinds"]
            if kind not in kinds:
                kinds.append(kind)
            return name
        name = f"{kind}{len(self.nodes)}"
        self.nodes.append((name, p, np.asarray(u, dtype=float)))
        G.add_node(name, kind=kind, kinds=[kind], p=float(p), **attrs)
        return name


def diagram(branches: Sequence[Branch], jumps: Iterable[JumpResult] = (), rtol: float = 1e-6,
            stability: str | None = None, *, merge: bool = False,
            curve_tol: float = CURVE_TOL) -> "nx.MultiDiGraph":
    """Assemble branches and jumps into a directed multigraph.

    Parameters
    ----------
    branches : sequence of Branch
        Traced branches (with stored states at least at their ends).
    jumps : iterable of JumpResult
        Snaps between branches.
    rtol : float
        Relative tolerance under which two points are the same node.
    stability : str, optional
        Stability label of the edges' ``stable`` and ``n_negative`` (default: each branch's primary
        label).
    merge : bool
        False (default): every run keeps its own edges, the record of what was traversed which a
        hysteresis loop needs (loading and unloading run along the same stable branch both ways).
        True: a diagram of curves: a branch's node inside another branch splits it, and a segment
        that repeats one already in the graph (a branch traced twice, or reached from its other end)
        is not added; the edge it repeats lists it under ``merged``.  Needs stored states.
    curve_tol : float
        With ``merge``: how far (scaled like ``rtol``) a point may be from a branch and lie on it
        (:func:`position_on`).

    Returns
    -------
    networkx.MultiDiGraph
        Node attributes: ``kind`` (first kind seen), ``kinds``, ``p``, ``observables``.
        Edge attributes: ``kind`` (``"branch"`` or ``"jump"``), and for branch segments ``branch``
        (index), ``start``/``stop`` (point indices), ``stable`` (True, False or None if mixed or
        unknown) and ``n_negative`` (sorted list of the Morse indices on the segment); with ``merge``,
        ``merged``: the segments of other branches that repeat this one (``branch``, ``start``,
        ``stop``, ``reverse``).  A node where a branch was split has ``"split"`` among its kinds.
    """
    G, _ = build_diagram(branches, jumps, rtol, stability, merge=merge, curve_tol=curve_tol)
    return G


def build_diagram(branches: Sequence[Branch], jumps: Iterable[JumpResult] = (), rtol: float = 1e-6,
                  stability: str | None = None, *, merge: bool = False,
                  curve_tol: float = CURVE_TOL) -> tuple["nx.MultiDiGraph", "NodeIndex"]:
    """:func:`diagram`, and the index that names its nodes (to find a node by its parameter and state)."""
    import networkx as nx

    G = nx.MultiDiGraph()
    index = NodeIndex(rtol)
    all_stops = [_stops(G, index, br) if len(br) else [] for br in branches]
    if merge:
        for br, stops in zip(branches, all_stops):
            if len(br) > 1:
                _split_at_landings(G, index, br, stops, curve_tol)
    for bi, (br, stops) in enumerate(zip(branches, all_stops)):
        if len(br) == 0:
            continue
        nneg = br.n_negative if stability is None else br.stability_by.get(stability, (None,))[0]
        for k, ((pos0, a, on0), (pos1, b, on1)) in enumerate(zip(stops[:-1], stops[1:])):
            if a == b:
                continue
            i0, i1 = int(pos0), int(pos1)
            if merge and _merge_into_existing(G, branches, bi, pos0, pos1, a, b, curve_tol):
                continue
            G.add_edge(a, b, kind="branch", branch=bi, start=i0, stop=i1,
                       **_segment_stability(nneg, i0, i1, k == 0, on1))
    for ji, jr in enumerate(jumps):
        a = index.find_or_add(G, "jump_from", jr.p, jr.u_from)
        b = index.find_or_add(G, "jump_to", jr.p, jr.u_to)
        G.add_edge(a, b, kind="jump", jump=ji, success=jr.success, energy_drop=jr.energy_from - jr.energy_to)
    return G, index


def save_diagram(G: "nx.MultiDiGraph", path: Any) -> Any:
    """Write a diagram of :func:`diagram` to ``path`` (``.npz`` with the graph as JSON), atomically.

    Nodes and edges keep every attribute; :func:`load_diagram` reads the same graph back.
    """
    def plain(attributes: dict) -> dict:
        return json_ready(dict(attributes), keep_nonfinite=True)

    graph = {"attributes": plain(G.graph),
             "nodes": [{"id": n, "attributes": plain(a)} for n, a in G.nodes(data=True)],
             "edges": [{"source": u, "target": v, "key": k, "attributes": plain(a)}
                       for u, v, k, a in G.edges(keys=True, data=True)]}
    return write_bundle(path, "contin-diagram", {"graph": graph}, {})


def load_diagram(path: Any) -> "nx.MultiDiGraph":
    """Read a diagram written by :func:`save_diagram`; raises :class:`contin.BranchFileError` if corrupt."""
    import networkx as nx

    header, _ = read_bundle(path, "contin-diagram", BranchFileError)
    try:
        graph = header["graph"]
        G = nx.MultiDiGraph(**graph["attributes"])
        for node in graph["nodes"]:
            G.add_node(node["id"], **node["attributes"])
        for edge in graph["edges"]:
            G.add_edge(edge["source"], edge["target"], key=edge["key"], **edge["attributes"])
    except Exception as exc:
        raise BranchFileError(f"{path}: inconsistent diagram data ({type(exc).__name__}: {exc})") from None
    return G


def _stops(G: "nx.MultiDiGraph", index: NodeIndex, br: Branch) -> list[tuple[float, str, bool]]:
    """Nodes along a branch: ``(position, node, whether the node is a stored point)``, start to end.

    The position is ``i + t``: the node lies between stored points ``i`` and ``i + 1``, the fraction
    ``t`` of the arclength between them on.
    """
    specials = sorted(br.special_points, key=lambda s: (s.index, s.s))
    # a switched branch starts at the branch point it left (its first stored point is a step off it)
    switched = bool(specials) and specials[0].label == "origin" and specials[0].index == 0
    stops = [] if switched else \
        [(0.0, index.find_or_add(G, "start", br.p[0], br.u[0], observables=_obs_at(br, 0)), False)]
    last = len(br) - 1
    for spt in specials:
        if spt.kind == "jump":
            continue
        idx = min(max(spt.index, 0), last)
        node = index.find_or_add(G, spt.kind, spt.p, np.asarray(spt.u), observables=dict(spt.observables),
                                 label=spt.label, located=spt.located)
        # a special point that is also a stored point (a run that ended on it) is not interior
        on_point = spt.p == br.p[idx] and (br.u.shape[0] != len(br) or np.array_equal(spt.u, br.u[idx]))
        stops.append((idx + _fraction(br, idx, spt.s), node, on_point))
    end = index.find_or_add(G, "end", br.p[last], br.u[last if br.u.shape[0] == len(br) else -1],
                            observables=_obs_at(br, last))
    stops.append((float(last), end, False))
    return stops


def _fraction(br: Branch, i: int, s: float) -> float:
    """Where arclength ``s`` lies between stored points ``i`` and ``i + 1`` (0 to 1; 0 where not known)."""
    if i + 1 >= len(br) or not np.isfinite(s):
        return 0.0
    step = float(br.s[i + 1] - br.s[i])
    return float(np.clip((s - br.s[i]) / step, 0.0, 1.0)) if step != 0.0 else 0.0


# ---- points on branches: splitting at landings, merging repeated segments ------------------------------

def _scaled_points(br: Branch, extra: Sequence[tuple[np.ndarray, float]] = ()) -> tuple[np.ndarray, np.ndarray]:
    """The branch's stored points ``(u, p)`` as rows, and the weights that scale them like node matching."""
    X = np.column_stack([np.asarray(br.u, dtype=float), np.asarray(br.p, dtype=float)])
    U = max([1.0, float(np.max(np.abs(X[:, :-1]), initial=0.0))]
            + [float(np.max(np.abs(u), initial=0.0)) for u, _ in extra])
    P = max([1.0, float(np.max(np.abs(X[:, -1]), initial=0.0))] + [abs(p) for _, p in extra])
    w = np.full(X.shape[1], 1.0 / U)
    w[-1] = 1.0 / P
    return X, w


def _cubic(X: np.ndarray, w: np.ndarray, i: int, t: np.ndarray) -> np.ndarray:
    """Points of the cubic through up to four stored points around step ``i``, at fractions ``t`` of the step.

    The parameter is the length of the scaled chords between the stored points (the run's own
    arclength is measured in its weighted norm, which may follow the curve less closely).
    """
    m = X.shape[0]
    lo = max(0, min(i - 1, m - 4))
    idx = np.arange(lo, min(lo + 4, m))
    chords = np.linalg.norm(np.diff(X[idx] * w, axis=0), axis=1)
    knots = np.concatenate([[0.0], np.cumsum(chords)])
    if np.any(chords == 0.0):  # repeated points: the chord between the two
        return (1.0 - t)[:, None] * X[i] + t[:, None] * X[i + 1]
    s = knots[i - lo] + t * (knots[i - lo + 1] - knots[i - lo])
    L = np.ones((t.size, idx.size))
    for a in range(idx.size):
        for b in range(idx.size):
            if a != b:
                L[:, a] *= (s - knots[b]) / (knots[a] - knots[b])
    return L @ X[idx]


def point_at(br: Branch, position: float) -> tuple[np.ndarray, float]:
    """The point ``(u, p)`` of the branch at ``position`` (``i + t``, as :func:`position_on` gives it)."""
    X, w = _scaled_points(br)
    i = int(min(max(np.floor(position), 0), len(br) - 2))
    x = _cubic(X, w, i, np.array([position - i]))[0]
    return x[:-1], float(x[-1])


def position_on(br: Branch, u: np.ndarray, p: float, tol: float = CURVE_TOL) -> float | None:
    """Where the point ``(u, p)`` lies on the branch: ``i + t`` (between stored points ``i`` and ``i + 1``), or None.

    The branch between two stored points is the cubic through four neighbouring ones; the point lies on it when its distance (largest component, the state relative to
    ``max(1, |u|)`` and the parameter to ``max(1, |p|)`` over the branch and the point) is at most ``tol``.
    A branch that kept no states (``store_states=False``) has no position for any point.
    """
    if len(br) < 2 or br.u.shape[0] != len(br):
        return None
    x = np.append(np.asarray(u, dtype=float), float(p))
    X, w = _scaled_points(br, [(np.asarray(u), float(p))])
    Y, y = X * w, x * w
    a, d = Y[:-1], np.diff(Y, axis=0)
    length2 = np.einsum("ij,ij->i", d, d)
    t = np.clip(np.einsum("ij,ij->i", y - a, d) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    chord = np.max(np.abs(a + t[:, None] * d - y), axis=1)
    # the curve leaves its chord by far less than the chord's length: only those steps can hold the point
    reach = tol + 0.5 * np.max(np.abs(d), axis=1)
    best: tuple[float, float] | None = None
    samples = np.linspace(0.0, 1.0, _SAMPLES)
    for i in np.flatnonzero(chord <= reach)[np.argsort(chord[chord <= reach])]:
        def gap(t: np.ndarray) -> np.ndarray:
            return np.linalg.norm(_cubic(X, w, int(i), t) * w - y, axis=1)
        k = int(np.argmin(gap(samples)))
        lo, hi = samples[max(k - 1, 0)], samples[min(k + 1, samples.size - 1)]
        for _ in range(40):  # the nearest point between the samples either side (golden-section search)
            a, b = hi - 0.618 * (hi - lo), lo + 0.618 * (hi - lo)
            ga, gb = gap(np.array([a, b]))
            lo, hi = (lo, b) if ga <= gb else (a, hi)
        t = 0.5 * (lo + hi)
        dist = float(np.max(np.abs(_cubic(X, w, int(i), np.array([t]))[0] * w - y)))
        if dist <= tol and (best is None or dist < best[1]):
            best = (int(i) + t, dist)
    return None if best is None else best[0]


def _split_at_landings(G: "nx.MultiDiGraph", index: NodeIndex, br: Branch, stops: list[tuple[float, str, bool]],
                       tol: float) -> None:
    """Add to ``stops`` every node of the graph that lies inside the branch (not at one of its own nodes)."""
    own = {node for _, node, _ in stops}
    for name, q, v in list(index.nodes):
        if name in own:
            continue
        position = position_on(br, v, q, tol)
        if position is None or position <= 0.0 or position >= len(br) - 1:
            continue
        if "split" not in G.nodes[name]["kinds"]:
            G.nodes[name]["kinds"].append("split")
        stops.append((position, name, False))
        own.add(name)
    stops.sort(key=lambda stop: stop[0])


def _merge_into_existing(G: "nx.MultiDiGraph", branches: Sequence[Branch], bi: int, pos0: float, pos1: float,
                         a: str, b: str, tol: float) -> bool:
    """Whether the segment ``a -> b`` of branch ``bi`` repeats an edge already in the graph (then it is noted there)."""
    mid_u, mid_p = point_at(branches[bi], 0.5 * (pos0 + pos1))
    for x, y in ((a, b), (b, a)):
        for data in (G.get_edge_data(x, y) or {}).values():
            if data.get("kind") != "branch":
                continue
            position = position_on(branches[data["branch"]], mid_u, mid_p, tol)
            if position is not None and data["start"] <= position <= data["stop"] + 1:
                data.setdefault("merged", []).append({"branch": bi, "start": int(pos0), "stop": int(pos1),
                                                      "reverse": x == b})
                return True
    return False


def _segment_stability(nneg: np.ndarray | None, i0: int, i1: int, first: bool, on1: bool) -> dict[str, Any]:
    """``stable`` and ``n_negative`` of the segment between stops at points ``i0`` and ``i1``."""
    if nneg is None:
        return {"stable": None}
    # interior points only: a fold or branch point itself has a zero eigenvalue
    lo = i0 if first else i0 + 1
    hi = i1 if on1 else i1 + 1
    inner = nneg[lo:hi] if hi > lo else nneg[i0:i1 + 1]
    vals = sorted({int(v) for v in inner})
    return {"n_negative": vals, "stable": (vals == [0]) if len(vals) == 1 else None}


def _obs_at(br: Branch, i: int) -> dict[str, float]:
    return {k: float(v[i]) for k, v in br.observables.items()}


def hysteresis_cycles(G: "nx.MultiDiGraph") -> list[list[str]]:
    """Directed cycles of the diagram that contain at least one jump (hysteresis loops)."""
    import networkx as nx

    simple = nx.DiGraph()
    for a, b, data in G.edges(data=True):
        is_jump = data.get("kind") == "jump"
        if simple.has_edge(a, b):
            simple[a][b]["jump"] = simple[a][b]["jump"] or is_jump
        else:
            simple.add_edge(a, b, jump=is_jump)
    cycles = []
    for cyc in nx.simple_cycles(simple):
        pairs = list(zip(cyc, cyc[1:] + cyc[:1]))
        if any(simple[a][b]["jump"] for a, b in pairs):
            cycles.append(cyc)
    return cycles
