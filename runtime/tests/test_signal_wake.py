"""A signal ends an idle node's wait at once, though its loop waits seconds between looks at its stop flag.

A Python signal handler runs only once the main thread is back in Python; a node waits in rcl_wait, so
SignalWake ends that wait. Without it an idle node polled 20 times a second (0.8 ms of CPU each) or
answered a stop late.
"""

import os
import signal
import subprocess
import sys
import threading
import time

from joshua_runtime.node import IDLE_WAIT_S
from joshua_runtime.stop_signal import SignalWake
from testsupport.compiled_settings import compiled_node
from testsupport.node_process import SHUTDOWN_CONTRACT_S

LONG_WAIT_S = 30.0  # the executor's timeout: a wait that ends sooner was ended by the signal
SIGNAL_AFTER_S = 0.3
WOKEN_WITHIN_S = 5.0  # generous for a busy machine, far below LONG_WAIT_S


def test_a_signal_ends_the_executors_wait_and_its_handler_runs_then(ros_domain):
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node("signal_wake_probe", context=context, start_parameter_services=False)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    handled = []
    previous = signal.signal(signal.SIGUSR1, lambda signum, _frame: handled.append(time.monotonic()))
    wake = SignalWake(node.create_guard_condition(lambda: None).trigger)
    try:
        timer = threading.Timer(SIGNAL_AFTER_S, os.kill, (os.getpid(), signal.SIGUSR1))
        started = time.monotonic()
        timer.start()
        executor.spin_once(timeout_sec=LONG_WAIT_S)
        returned = time.monotonic()
        timer.join()
        assert returned - started < WOKEN_WITHIN_S, f"the wait ended {returned - started:.1f} s after it began"
        assert handled and started <= handled[0] <= returned, "the handler did not run while spin_once returned"
    finally:
        wake.close()
        signal.signal(signal.SIGUSR1, previous)
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown(context=context)
    assert not wake.thread.is_alive()
    assert signal.set_wakeup_fd(-1) == -1, "close() gave the interpreter's wakeup descriptor back"


CLOSE_WITH_A_CHILD_HOLDING_THE_PIPE = f"""
import os, signal, time
from joshua_runtime.stop_signal import SignalWake
wake = SignalWake(lambda: None)
child = os.fork()
if child == 0:
    time.sleep({LONG_WAIT_S})
    os._exit(0)
wake.close()
print("closed", wake.thread.is_alive(), signal.set_wakeup_fd(-1), flush=True)
os.kill(child, signal.SIGKILL)
os.waitpid(child, 0)
"""


def test_close_ends_the_thread_while_a_forked_child_holds_the_pipe_open():
    done = subprocess.run(
        [sys.executable, "-c", CLOSE_WITH_A_CHILD_HOLDING_THE_PIPE], capture_output=True, text=True, timeout=LONG_WAIT_S
    )
    assert (done.returncode, done.stdout) == (0, "closed False -1\n"), done.stderr


def test_a_node_with_nothing_to_do_for_seconds_stops_within_the_contract(start_node):
    settings = compiled_node(
        'name: "idle" type: MOCK_ENCODER_PUBLISHER topic_name: "/idle/joint_states" rate_hz: 0.05 '
        'joint_names: ["a"] device_ids: [1]'
    )
    for signum in (signal.SIGINT, signal.SIGTERM):
        node = start_node(settings)
        node.read_stderr_until("ready:")
        time.sleep(IDLE_WAIT_S / 2)  # mid-wait: nothing but the signal ends it sooner
        code, seconds, stderr = node.stop(signum)
        assert code == 0, stderr
        assert seconds < SHUTDOWN_CONTRACT_S, f"exit took {seconds:.3f} s after {signal.Signals(signum).name}"
