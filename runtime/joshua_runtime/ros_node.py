"""rclpy nodes without the services that nobody calls on them: parameter services and the type description service.

An rclpy node answers six parameter services and the type description service by default: 14 endpoints beside
its own topics, which every other participant of the domain discovers and matches. joshua's processes take their
settings from the build, never from ROS parameters, so they make none of them (as the C++ nodes make none): a
32-node robot's discovery has about a quarter of the endpoints to exchange.
"""

TYPE_DESCRIPTION_SERVICE_PARAMETER = "start_type_description_service"  # rclpy's switch for ~/get_type_description


def create_ros_node(name: str, **options):
    """`rclpy.create_node(name, **options)`, without parameter services and the type description service."""
    import rclpy
    from rclpy.parameter import Parameter

    return rclpy.create_node(
        name,
        start_parameter_services=False,
        parameter_overrides=[Parameter(TYPE_DESCRIPTION_SERVICE_PARAMETER, value=False)],
        **options,
    )
