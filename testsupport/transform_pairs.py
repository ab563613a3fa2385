"""The /tf messages a test client heard, each with the JointState of the same stamp it heard too."""


def stamp(header) -> tuple[int, int]:
    return header.stamp.sec, header.stamp.nanosec


def transforms_with_states(ros_client, state_topic: str, tf_topic: str = "/tf") -> list[tuple]:
    """(TFMessage, JointState) for every transform `ros_client` kept whose joint state, by stamp, it kept too. A
    client may match the joint states' publisher seconds after the transforms' on a busy machine: wait until
    this holds enough pairs before comparing."""
    states = {stamp(m.header): m for m in ros_client.messages(state_topic)}
    return [
        (tf, states[stamp(tf.transforms[0].header)])
        for tf in ros_client.messages(tf_topic)
        if stamp(tf.transforms[0].header) in states
    ]
