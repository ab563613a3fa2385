"""A node that crashes in native code says where: the Python stack of its threads, then it dies of the signal."""

import signal

from testsupport.compiled_settings import compiled_node


def test_a_node_killed_by_sigsegv_prints_its_stack_and_dies_of_the_signal(start_node):
    settings = compiled_node(
        'name: "crashing" type: MOCK_ENCODER_PUBLISHER topic_name: "/crashing/joint_states" rate_hz: 5 '
        'joint_names: ["a"] device_ids: [1]'
    )
    node = start_node(settings)
    node.read_stderr_until("ready:")
    code, _, stderr = node.stop(signal.SIGSEGV)
    assert code == -signal.SIGSEGV, stderr
    assert "Fatal Python error: Segmentation fault" in stderr, stderr
    assert "joshua_runtime/node.py" in stderr and "in run" in stderr, stderr
