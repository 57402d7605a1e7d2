"""Cycle-safe graph walks without recursion: every walk over names that a file links together
(URDF parent links, SRDF subgroups, geometry clones, mimic chains) goes through here or keeps
its own visited set, so a cycle or a very deep chain in the input is an error, never a hang or
a ``RecursionError``."""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Iterator, Sequence
from typing import TypeVar

__all__ = ["find_cycle", "nodes_on_cycles", "postorder", "reachable", "show_path"]

T = TypeVar("T", bound=Hashable)
_OPEN, _DONE = 1, 2


def show_path(path: Sequence[object], limit: int = 8) -> str:
    """``a -> b -> c`` for a message, the middle left out of a long path (one short line)."""
    names = [str(p) for p in path]
    if len(names) > limit:
        names = [*names[: limit // 2], f"... ({len(names) - limit} more)", *names[-limit // 2 :]]
    return " -> ".join(names)


def _dfs(
    start: T,
    children: Callable[[T], Iterable[T]],
    state: dict[T, int],
    order: list[T],
    post: list[T] | None = None,
) -> list[T] | None:
    """Depth-first from ``start`` (skipping nodes already in ``state``); appends nodes to
    ``order`` in preorder (and to ``post`` in postorder, walking on past cycles); returns the
    first cycle as a closed path ``[a, b, a]`` or None."""
    if start in state:
        return None
    cycle: list[T] | None = None
    state[start] = _OPEN
    order.append(start)
    path: list[T] = [start]
    stack: list[Iterator[T]] = [iter(children(start))]
    while stack:
        nxt = next(stack[-1], None)
        if nxt is None:
            stack.pop()
            done = path.pop()
            state[done] = _DONE
            if post is not None:
                post.append(done)
            continue
        seen = state.get(nxt)
        if seen == _OPEN:
            cycle = cycle or [*path[path.index(nxt) :], nxt]
            if post is None:
                return cycle
            continue
        if seen == _DONE:
            continue
        state[nxt] = _OPEN
        order.append(nxt)
        path.append(nxt)
        stack.append(iter(children(nxt)))
    return cycle


def postorder(nodes: Iterable[T], children: Callable[[T], Iterable[T]]) -> list[T]:
    """Every node reachable from ``nodes``, each once, children before parents (an edge that
    closes a cycle is skipped, so use :func:`nodes_on_cycles` to know which nodes are cyclic)."""
    state: dict[T, int] = {}
    order: list[T] = []
    post: list[T] = []
    for n in nodes:
        _dfs(n, children, state, order, post)
    return post


def reachable(start: T, children: Callable[[T], Iterable[T]]) -> tuple[list[T], list[T] | None]:
    """Every node reachable from ``start`` (``start`` first, depth-first preorder, each once)
    and the first cycle met as a closed path ``[a, b, a]`` (None when there is none).

    ``children`` may raise (e.g. for an unknown name); ``None`` is not a valid node.
    """
    order: list[T] = []
    cycle = _dfs(start, children, {}, order)
    return order, cycle


def find_cycle(nodes: Iterable[T], children: Callable[[T], Iterable[T]]) -> list[T] | None:
    """The first cycle reachable from any of ``nodes`` as a closed path, or None."""
    state: dict[T, int] = {}
    order: list[T] = []
    for n in nodes:
        cycle = _dfs(n, children, state, order)
        if cycle is not None:
            return cycle
    return None


def nodes_on_cycles(nodes: Iterable[T], children: Callable[[T], Iterable[T]]) -> set[T]:
    """Every node that lies on a cycle (a node that reaches itself), in linear time.

    Tarjan's strongly connected components, iteratively: a component of two or more nodes, or
    one node that is its own child, is cyclic.
    """
    index: dict[T, int] = {}
    low: dict[T, int] = {}
    on_stack: set[T] = set()
    stack: list[T] = []
    out: set[T] = set()
    for root in nodes:
        if root in index:
            continue
        work: list[tuple[T, Iterator[T]]] = [(root, iter(children(root)))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, it = work[-1]
            child = next(it, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(children(child))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                    if child == node:
                        out.add(node)
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                component: list[T] = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    out.update(component)
    return out
