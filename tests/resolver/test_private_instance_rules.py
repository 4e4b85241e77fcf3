"""The rule that decides which private instances a robot gets (docs/deployment.md,
"Private instances"), case by case, on small lines written here: two robots, Alpha and
Beta, and a cloud whose private and shared nodes are wired for each case."""

from __future__ import annotations

from pathlib import Path

from spl.resolver.architecture.placement import Placement
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

ROBOTS = """system Rules
robot container Alpha {
    endpoint robot_id "alpha" url "wss://x.example.org:9000/" user "u" password env "P"
    topic Out : std_msgs/String name "/alpha/out"
    topic In  : std_msgs/String name "/alpha/in"
    node Sensor { implementation a/sensor publishes out -> Out }
    node Display { implementation a/display subscribes in <- In }
    node Caller { implementation a/caller calls ask : std_srvs/Trigger }
}
robot container Beta {
    endpoint robot_id "beta" url "wss://x.example.org:9000/" user "u" password env "P"
    topic Out : std_msgs/String name "/beta/out"
    topic In  : std_msgs/String name "/beta/in"
    node Sensor { implementation b/sensor publishes out -> Out }
    node Display { implementation b/display subscribes in <- In }
    node Caller { implementation b/caller calls ask : std_srvs/Trigger }
}
"""
BRIDGES = """bridge Alpha.Out -> Cloud.AlphaOut
bridge Beta.Out -> Cloud.BetaOut
bridge Cloud.AlphaIn -> Alpha.In
bridge Cloud.BetaIn -> Beta.In
"""
TOPICS = """    topic AlphaOut : std_msgs/String name "/alpha/out"
    topic BetaOut  : std_msgs/String name "/beta/out"
    topic AlphaIn  : std_msgs/String name "/alpha/in"
    topic BetaIn   : std_msgs/String name "/beta/in"
    topic Mid      : std_msgs/String name "/mid"
    topic Mid2     : std_msgs/String name "/mid2"
"""


def instances(tmp_path: Path, cloud_nodes: str, bridges: str = "") -> dict[str, set[str]]:
    """Robot -> the private nodes it gets of the cloud holding ``cloud_nodes``."""
    folder = tmp_path / "rules"
    folder.mkdir(parents=True)
    tsm = f"{ROBOTS}cloud container Cloud {{\n{TOPICS}{cloud_nodes}}}\n{BRIDGES}{bridges}"
    (folder / "r.tsm").write_text(tsm, encoding="utf-8")
    (folder / "r.fm").write_text("feature model Rules\nroot Rules { }\n", encoding="utf-8")
    (folder / "r.rm").write_text('resolution model Rules\ntsm "r.tsm"\nfm "r.fm"\n', "utf-8")
    product = resolve(load_product_line(folder), selection_from_list("Rules")).product
    placement = Placement(product.system, [], flows=product.flows)
    found: dict[str, set[str]] = {"alpha": set(), "beta": set()}
    for instance in placement.cloud_instances():
        if instance.place.kind == "private":
            found[instance.place.owner] |= {n.name for n in instance.nodes}
    return found


def test_an_instance_only_another_robot_feeds_is_not_deployed(tmp_path):
    # Alpha's data reaches P; P's output reaches Beta's display, but Beta's instance of
    # P would get none of Alpha's data (a private instance takes no other robot's)
    nodes = """    node P { implementation c/p subscribes i <- AlphaOut publishes o -> BetaIn }
"""
    assert instances(tmp_path, nodes) == {"alpha": {"P"}, "beta": set()}


def test_a_chain_of_private_instances_of_one_robot_is_kept_whole(tmp_path):
    nodes = """    node P { implementation c/p subscribes i <- AlphaOut publishes o -> Mid }
    node Q { implementation c/q subscribes i <- Mid publishes o -> Mid2 }
    node R { implementation c/r subscribes i <- Mid2 }
"""
    assert instances(tmp_path, nodes) == {"alpha": {"P", "Q", "R"}, "beta": set()}


def test_a_source_is_kept_for_the_robots_it_feeds(tmp_path):
    # T is fed by nothing (a timer): it feeds Alpha, directly, and nothing of Beta
    nodes = """    node T { implementation c/t publishes o -> AlphaIn }
"""
    assert instances(tmp_path, nodes) == {"alpha": {"T"}, "beta": set()}


def test_a_source_feeding_an_instance_the_robot_keeps_is_kept(tmp_path):
    # K is a sink Alpha feeds; the timer T feeds K too: Alpha's K needs its T
    nodes = """    node K { implementation c/k subscribes a <- AlphaOut subscribes t <- Mid }
    node T { implementation c/t publishes o -> Mid }
"""
    assert instances(tmp_path, nodes) == {"alpha": {"K", "T"}, "beta": set()}


def test_a_shared_node_another_robot_feeds_keeps_an_instance_only_where_it_feeds_the_robot(
    tmp_path,
):
    # S (public) is fed by Beta alone. P, fed by S, feeds Alpha: Alpha's P gets S's data
    # and gives it to Alpha, so Alpha keeps it. Q, fed by S too, feeds nothing of Alpha
    # and Alpha feeds it nothing: only Beta (whose data reaches it through S) keeps it.
    nodes = """    node S sharing public {
        implementation c/s subscribes i <- BetaOut publishes o -> Mid
    }
    node P { implementation c/p subscribes i <- Mid publishes o -> AlphaIn }
    node Q { implementation c/q subscribes i <- Mid }
"""
    assert instances(tmp_path, nodes) == {"alpha": {"P"}, "beta": {"P", "Q"}}


def test_a_loop_nothing_starts_carries_no_data(tmp_path):
    # S (public) and X feed each other and nothing else feeds either: no data ever runs
    # in the loop, so P, fed by S alone, has nothing to give Alpha
    nodes = """    node S sharing public {
        implementation c/s subscribes i <- Mid2 publishes o -> Mid
    }
    node X { implementation c/x subscribes i <- Mid publishes o -> Mid2 }
    node P { implementation c/p subscribes i <- Mid publishes o -> AlphaIn }
"""
    assert instances(tmp_path, nodes) == {"alpha": set(), "beta": set()}
    # Alpha's sensor feeding the loop starts it: Alpha's data reaches X and P
    bridges = "bridge Alpha.Out -> Cloud.Mid2\n"
    assert instances(tmp_path / "fed", nodes, bridges) == {"alpha": {"P", "X"}, "beta": set()}


def test_an_input_no_flow_feeds_counts_as_a_source(tmp_path):
    # what feeds U.i is not in the model (a timer, a driver, or a gap SPL045 warns of):
    # U makes its own data, which reaches Beta
    nodes = """    node U { implementation c/u subscribes i <- Mid2 publishes o -> BetaIn }
"""
    assert instances(tmp_path, nodes) == {"alpha": set(), "beta": {"U"}}


def test_a_server_gets_an_instance_for_the_robots_that_call_it(tmp_path):
    nodes = """    node Server { implementation c/s provides ask : std_srvs/Trigger name "/ask" }
"""
    bridges = "bridge Alpha.Caller.ask -> Cloud.Server.ask\n"
    assert instances(tmp_path, nodes, bridges) == {"alpha": {"Server"}, "beta": set()}


def test_answers_reach_only_a_client_that_calls(tmp_path):
    # Both robots call the public Database. C, a private client of it, is fed by
    # Alpha's data: Alpha keeps it. Beta's C would call nothing (no data reaches it),
    # so the Database's answers, which Beta's calls shape, never reach it: none for Beta.
    # D only calls (a source): the Database's answers carry both robots' calls to it,
    # so each robot keeps a D.
    nodes = """    node Database sharing public {
        implementation c/db
        provides ask : std_srvs/Trigger name "/ask"
        provides query : std_srvs/Trigger name "/query"
    }
    node C { implementation c/c subscribes i <- AlphaOut calls q -> Database.query }
    node D { implementation c/d calls q -> Database.query }
"""
    bridges = (
        "bridge Alpha.Caller.ask -> Cloud.Database.ask\n"
        "bridge Beta.Caller.ask -> Cloud.Database.ask\n"
    )
    assert instances(tmp_path, nodes, bridges) == {"alpha": {"C", "D"}, "beta": {"D"}}


def test_a_node_no_flow_joins_with_any_robot_runs_nowhere(tmp_path):
    nodes = """    node Lonely { implementation c/lonely subscribes i <- Mid2 publishes o -> Mid }
"""
    assert instances(tmp_path, nodes) == {"alpha": set(), "beta": set()}
