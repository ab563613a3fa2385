"""What a run of the supervisor came to: its exit code, and last lines for lost data or an internal error."""

from joshua_codegen.supervisor.policy import (
    EXIT_CRITICAL,
    EXIT_DATA_LOST,
    EXIT_ESCALATED,
    EXIT_INTERNAL,
    EXIT_NODE_FAILED,
    EXIT_OK,
)
from joshua_codegen.supervisor.robot import ROBOT


class Outcome:
    """Failures seen while the robot ran; the first that applies decides the exit code."""

    def __init__(self):
        self.internal_error = False  # the supervisor hit a bug of its own: the robot was stopped
        self.critical_failure = False  # a critical node failed for good: the robot was stopped
        self.node_failure = False  # a non-critical node failed for good
        self.escalated = False  # stopping needed SIGTERM or SIGKILL
        self.data_lost: list[dict] = []  # specs of the nodes that exited with the node code for data lost

    def on_node_exit(self, spec: dict, code: int | None) -> None:
        if code == ROBOT["node_exit_codes"]["data_lost"] and spec not in self.data_lost:
            self.data_lost.append(spec)

    def exit_code(self) -> int:
        if self.internal_error:
            return EXIT_INTERNAL
        if self.data_lost:
            return EXIT_DATA_LOST
        if self.critical_failure:
            return EXIT_CRITICAL
        if self.escalated:
            return EXIT_ESCALATED
        return EXIT_NODE_FAILED if self.node_failure else EXIT_OK

    def last_lines(self) -> list[str]:
        """One line per node that lost data (which node, where the data should have gone); one for an internal
        error."""
        lines = []
        if self.internal_error:
            lines.append(
                f"internal error: a bug in supervisor.py stopped the robot (exit code {EXIT_INTERNAL}); "
                "its traceback is above"
            )
        for spec in self.data_lost:
            where = f" to {spec['output_directory']}" if spec["output_directory"] else ""
            lines.append(
                f"data lost: node {spec['name']} could not save data it had taken in{where} "
                f"(exit code {ROBOT['node_exit_codes']['data_lost']}; its error line above says what)"
            )
        return lines
