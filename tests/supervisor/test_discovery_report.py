"""What `ctl status` says of the Discovery Server: the host agent's last report, unknown once the agent ended."""

from types import SimpleNamespace

from joshua_codegen.supervisor.discovery_report import DiscoveryReport

SERVER = "10.0.0.2:11811"


def agent():
    return SimpleNamespace(name="host_agent_gpu", state="running")


def test_unknown_until_the_agent_reports_then_its_state_since_it_changed():
    report = DiscoveryReport(SERVER)
    assert report.as_dict(5.0) == {
        "server": SERVER,
        "reachable": None,
        "since_s": None,
        "detail": "not reported yet (the host's agent probes the server)",
    }
    reporter = agent()
    report.record(reporter, "reachable", "discovery server reachable", 10.0)
    report.record(reporter, "reachable", "discovery server reachable", 12.0)
    assert report.as_dict(13.0) | {"detail": ""} == {"server": SERVER, "reachable": True, "since_s": 3.0, "detail": ""}
    report.record(reporter, "unreachable", "discovery server 10.0.0.2:11811 unreachable: ...", 20.0)
    assert report.as_dict(24.5) == {
        "server": SERVER,
        "reachable": False,
        "since_s": 4.5,
        "detail": "discovery server 10.0.0.2:11811 unreachable: ...",
    }


def test_forgotten_when_its_agent_ends_and_only_then():
    report, reporter = DiscoveryReport(SERVER), agent()
    report.record(reporter, "unreachable", "unreachable", 1.0)
    report.forget(agent(), 2.0)  # another node's end changes nothing
    assert report.as_dict(3.0)["reachable"] is False
    report.forget(reporter, 4.0)
    assert report.as_dict(5.0) == {
        "server": SERVER,
        "reachable": None,
        "since_s": 1.0,
        "detail": "host_agent_gpu ended: the server is not watched until it runs again",
    }


def test_a_robot_without_a_discovery_server_has_no_report():
    assert DiscoveryReport.of_robot() is None  # the placeholder robot has none
