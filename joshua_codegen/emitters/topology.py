"""topology.dot and topology.mmd: the node/topic graph for Graphviz and Mermaid."""

from types import SimpleNamespace

from joshua_codegen.model import Robot
from joshua_codegen.render import Context, template
from joshua_core.node_types import SIMULATION_ENGINE


def graph(robot: Robot) -> SimpleNamespace:
    """Nodes, topics and edges with stable ids (n0.., t0..) shared by both formats (attributes, as the
    templates read them)."""
    node_ids = {node.name: f"n{i}" for i, node in enumerate(robot.nodes)}
    engines = [p for p in robot.processes if p.node_type == SIMULATION_ENGINE.name]
    for i, process in enumerate(engines):
        node_ids[process.name] = f"s{i}"
    topic_ids = {topic.name: f"t{i}" for i, topic in enumerate(robot.topics)}
    edges = []
    for topic in robot.topics:
        for endpoint in topic.publishers:
            edges.append((node_ids[endpoint.node], topic_ids[topic.name], endpoint.qos))
        for endpoint in topic.subscribers:
            edges.append((topic_ids[topic.name], node_ids[endpoint.node], endpoint.qos))
    simulated = [(node_ids[n.simulated_by], node_ids[n.name]) for n in robot.nodes if n.simulated_by]
    return SimpleNamespace(node_ids=node_ids, topic_ids=topic_ids, edges=edges, simulated=simulated, engines=engines)


def qos_label(qos) -> str:
    history = f"depth {qos.depth}" if qos.history == "KEEP_LAST" else "keep all"
    return f"{qos.reliability.lower()}, {qos.durability.lower()}, {history}"


def render_dot(robot: Robot) -> str:
    return template("topology.dot.j2", robot=robot, g=graph(robot), qos_label=qos_label)


def render_mermaid(robot: Robot) -> str:
    return template("topology.mmd.j2", robot=robot, g=graph(robot), qos_label=qos_label)


def emit(robot: Robot, context: Context) -> dict[str, str]:
    return {"topology.dot": render_dot(robot), "topology.mmd": render_mermaid(robot)}
