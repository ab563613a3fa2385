"""What the event stream tells the page besides the robot's data: the server's clock, when each event
was published, and which node actions are under way (a restart waits for the old process to end)."""

import threading
import urllib.request

from dashboard_support import EVENTS_TIMEOUT_S, EventReader, dashboard_token, free_port, running_robot

# A node that ignores SIGINT, so that its restart lasts the robot's SIGINT grace.
STUBBORN = """robot_config {{ name: "events_robot" mode: MODE_TELEOPERATION
  shutdown {{ sigint_grace_s: 2 sigterm_grace_s: 1 }}
  node {{ name: "stubborn" type: CUSTOM executable: "/bin/sh" args: ["-c", "trap '' INT; exec sleep 600"] }}
  dashboard {{ port: {port} }}
}}
"""


def test_events_carry_the_server_clock_and_the_actions_under_way(tmp_path, ros_env):
    port = free_port()
    with running_robot(STUBBORN.format(port=port), tmp_path, ros_env, port) as control_socket:
        url, token = f"http://127.0.0.1:{port}", dashboard_token(control_socket)
        reader = EventReader(url, token)
        kind, clock, arrived = reader.wait_for(lambda kind, _data: kind == "clock", "clock")
        assert abs(clock["server_time_s"] - arrived) < 1.0  # one machine: one clock
        _, status, arrived = reader.wait_for(lambda kind, data: kind == "status" and "nodes" in data, "status")
        assert abs(status["server_time_s"] - arrived) < 2.0
        reader.wait_for(
            lambda kind, data: kind == "clock" and data["server_time_s"] > clock["server_time_s"], "later clock"
        )

        request = urllib.request.Request(
            url + "/api/nodes/stubborn/restart", method="POST", headers={"Authorization": f"Bearer {token}"}
        )
        restart = threading.Thread(target=lambda: urllib.request.urlopen(request, timeout=EVENTS_TIMEOUT_S).read())
        restart.start()
        reader.wait_for(lambda kind, data: kind == "actions" and data["pending"] == {"stubborn": "restart"}, "pending")
        restart.join(EVENTS_TIMEOUT_S)
        reader.wait_for(lambda kind, data: kind == "actions" and data["pending"] == {}, "finished")
