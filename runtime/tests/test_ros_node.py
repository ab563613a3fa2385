"""A node of the runtime offers its own topics and nothing else: no parameter services and no type description
service, which every participant of the domain would otherwise discover and match (14 endpoints a node)."""

from testsupport.compiled_settings import compiled_settings

DISCOVERY_TIMEOUT_S = 20.0
SETTLE_S = 2.0  # after its publisher is seen: what else the node offers has come with it by then
ROBOT = """robot_config { name: "r" mode: MODE_TELEOPERATION
  node { name: "lean" type: MOCK_ENCODER_PUBLISHER topic_name: "/lean/joint_states" } }"""


def test_a_python_node_offers_no_service_and_only_its_own_and_rclpys_topics(start_node, ros_client):
    node = start_node(compiled_settings(ROBOT)["lean"])
    assert ros_client.publishers_info("/lean/joint_states", DISCOVERY_TIMEOUT_S), node.failure()
    ros_client.spin_until(lambda: False, SETTLE_S)
    graph = ros_client.node
    assert graph.get_service_names_and_types_by_node("lean", "/") == [], node.failure()
    published = {name for name, _ in graph.get_publisher_names_and_types_by_node("lean", "/")}
    assert published == {"/lean/joint_states", "/rosout", "/parameter_events"}, node.failure()
