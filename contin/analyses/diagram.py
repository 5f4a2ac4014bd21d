"""Bifurcation diagrams as ``networkx`` graphs.

Nodes are the end points and special points of branches; points that coincide (same parameter and
state within a tolerance) are one node, so a branch traced twice or a jump that lands where another
branch starts joins the pieces.  Edges are branch segments between consecutive nodes (with their
stability) and jumps.  A loading-unloading hysteresis loop therefore shows up as a directed cycle.
The plots that read branches and jumps are in :mod:`contin.plot.branches`.
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

__all__ = ["diagram", "hysteresis_cycles", "save_diagram", "load_diagram"]


class _NodeIndex:
    def __init__(self, rtol: float) -> None:
        self.rtol = rtol
        self.nodes: list[tuple[str, float, np.ndarray]] = []

    def find_or_add(self, G: "nx.MultiDiGraph", kind: str, p: float, u: np.ndarray, **attrs: Any) -> str:
        for name, q, v in self.nodes:
            scale = max(1.0, float(np.max(np.abs(v), initial=0.0)))
            if abs(p - q) <= self.rtol * max(1.0, abs(p)) and v.shape == u.shape and \
                    float(np.max(np.abs(u - v), initial=0.0)) <= self.rtol * scale:
                kinds = G.nodes[name]["kinds"]
                if kind not in kinds:
                    kinds.append(kind)
                return name
        name = f"{kind}{len(self.nodes)}"
        self.nodes.append((name, p, np.asarray(u, dtype=float)))
        G.add_node(name, kind=kind, kinds=[kind], p=float(p), **attrs)
        return name


def diagram(branches: Sequence[Branch], jumps: Iterable[JumpResult] = (), rtol: float = 1e-6,
            stability: str | None = None) -> "nx.MultiDiGraph":
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

    Returns
    -------
    networkx.MultiDiGraph
        Node attributes: ``kind`` (first kind seen), ``kinds``, ``p``, ``observables``.
        Edge attributes: ``kind`` (``"branch"`` or ``"jump"``), and for branch segments ``branch``
        (index), ``start``/``stop`` (point indices), ``stable`` (True, False or None if mixed or
        unknown) and ``n_negative`` (sorted list of the Morse indices on the segment).
    """
    import networkx as nx

    G = nx.MultiDiGraph()
    index = _NodeIndex(rtol)
    for bi, br in enumerate(branches):
        if len(br) == 0:
            continue
        nneg = br.n_negative if stability is None else br.stability_by.get(stability, (None,))[0]
        stops = _stops(G, index, br)
        for k, ((i0, a, on0), (i1, b, on1)) in enumerate(zip(stops[:-1], stops[1:])):
            if a != b:
                G.add_edge(a, b, kind="branch", branch=bi, start=int(i0), stop=int(i1),
                           **_segment_stability(nneg, i0, i1, k == 0, on1))
    for ji, jr in enumerate(jumps):
        a = index.find_or_add(G, "jump_from", jr.p, jr.u_from)
        b = index.find_or_add(G, "jump_to", jr.p, jr.u_to)
        G.add_edge(a, b, kind="jump", jump=ji, success=jr.success, energy_drop=jr.energy_from - jr.energy_to)
    return G


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


def _stops(G: "nx.MultiDiGraph", index: _NodeIndex, br: Branch) -> list[tuple[int, str, bool]]:
    """Nodes along a branch: ``(point index, node, whether the node is a stored point)``, start to end."""
    stops = [(0, index.find_or_add(G, "start", br.p[0], br.u[0], observables=_obs_at(br, 0)), False)]
    last = len(br) - 1
    for spt in sorted(br.special_points, key=lambda s: (s.index, s.s)):
        if spt.kind == "jump":
            continue
        idx = min(max(spt.index, 0), last)
        node = index.find_or_add(G, spt.kind, spt.p, np.asarray(spt.u), observables=dict(spt.observables),
                                 label=spt.label, located=spt.located)
        # a special point that is also a stored point (a run that ended on it) is not interior
        on_point = spt.p == br.p[idx] and (br.u.shape[0] != len(br) or np.array_equal(spt.u, br.u[idx]))
        stops.append((idx, node, on_point))
    end = index.find_or_add(G, "end", br.p[last], br.u[last if br.u.shape[0] == len(br) else -1],
                            observables=_obs_at(br, last))
    stops.append((last, end, False))
    return stops


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
