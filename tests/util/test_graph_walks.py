"""The cycle-safe graph walks of util.graph: reachability, cycles, nodes on cycles, postorder."""

from __future__ import annotations

from xrdf_tools.util.graph import find_cycle, reachable


def test_graph_helpers() -> None:
    edges = {"a": ["b", "c"], "b": ["d"], "c": ["d"], "d": []}
    assert reachable("a", edges.__getitem__) == (["a", "b", "d", "c"], None)
    edges["d"] = ["b"]
    assert reachable("a", edges.__getitem__)[1] == ["b", "d", "b"]
    assert find_cycle(["c"], edges.__getitem__) == ["d", "b", "d"]
    chain = {i: [i + 1] for i in range(100_000)}
    assert find_cycle(chain, lambda i: chain.get(i, [])) is None


def test_nodes_on_cycles() -> None:
    from xrdf_tools.util.graph import nodes_on_cycles, show_path

    edges = {"a": ["b"], "b": ["c", "a"], "c": ["c"], "d": ["a"], "e": []}
    assert nodes_on_cycles(edges, edges.__getitem__) == {"a", "b", "c"}
    chain = {i: [i + 1] for i in range(100_000)}
    chain[100_000] = [0]
    assert len(nodes_on_cycles(chain, chain.__getitem__)) == 100_001
    assert show_path(range(20)) == "0 -> 1 -> 2 -> 3 -> ... (12 more) -> 16 -> 17 -> 18 -> 19"


def test_postorder_puts_children_first() -> None:
    from xrdf_tools.util.graph import postorder

    edges = {"a": ["b", "c"], "b": [], "c": ["b"], "d": ["d"]}
    order = postorder(edges, edges.__getitem__)
    assert order.index("b") < order.index("c") < order.index("a") and "d" in order
