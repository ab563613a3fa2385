"""What every rule reads: the description, source positions, derived node names and a topic index.

Everything is computed once per check and indexed in dicts, so each rule runs in linear time.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from functools import cached_property

from google.protobuf.descriptor import FieldDescriptor

from joshua_codegen import defaults, msg_catalog, topology
from joshua_codegen.model import Robot
from joshua_codegen.plan import plan
from joshua_codegen.positions import Path, SourceMap, node_path
from joshua_codegen.render import effective_prefix
from joshua_core.schema import Node, RobotDescription
from joshua_core.schema import robot_config_pb2 as pb


@dataclass(frozen=True)
class Finding:
    """One problem found by a rule: where (a message path), what, and the other side.

    `column` (with `end_column`), when given, points inside the written value: the exact characters."""

    at: Path
    message: str
    related: tuple[tuple[Path, str], ...] = ()
    column: int | None = None
    end_column: int | None = None


@dataclass(frozen=True)
class NodeView:
    index: int
    node: Node
    name: str  # the node's own name or the one derived from its type

    @property
    def path(self) -> Path:
        return node_path(self.index)

    def at(self, *fields: str | int) -> Path:
        """Path of a field of this node (located at the node when the field is not written)."""
        return self.path + fields

    @property
    def label(self) -> str:
        """`INFERENCE node "policy"`, for messages."""
        return f'{defaults.type_name(self.node.type)} node "{self.name}"'


@dataclass(frozen=True)
class Endpoint:
    """A node's publication or subscription of one resolved topic."""

    view: NodeView
    topic: str  # fully qualified
    message_type: str  # "" when not known (input_topics take their publishers' type)
    qos: dict | None  # None for input_topics, whose QoS follows their publishers
    at: Path  # the field that declares the topic
    implied: bool = False  # declared by the node type itself, not by a field (topology.Declaration)


class RuleContext:
    def __init__(
        self,
        description: RobotDescription,
        source: SourceMap,
        sources: dict[str, str] | None = None,
        prefix: str | None = None,
        unknown_nodes: frozenset[int] = frozenset(),
    ):
        self.description = description
        self.config = description.robot_config
        self.source = source
        self.sources = sources or {}  # texts by path (the file, and `--set` lines), for exact columns
        self.prefix = effective_prefix(self.config.name, prefix)  # where the output lives on the robot
        names = defaults.node_names(self.config)
        # Nodes the loader could not read whole are left out (see rules/__init__.py).
        self.unknown_nodes = unknown_nodes
        self.nodes = [NodeView(i, node, names[i]) for i, node in enumerate(self.config.node) if i not in unknown_nodes]

    @cached_property
    def robot(self) -> Robot:
        """The planned model; only for "plan"-stage rules, which run when no error was found before."""
        return plan(self.description, self.source.path)

    def written(self, path: Path) -> bool:
        """Whether the path was written in the file (or set by an override)."""
        return self.source.get(path) is not None

    @cached_property
    def typed_nodes(self) -> list[NodeView]:
        """Nodes whose type is set; per-type rules skip the others (E103 reports them)."""
        return [view for view in self.nodes if view.node.type != pb.NODE_TYPE_UNSPECIFIED]

    def lacking(self, field: str) -> list[NodeView]:
        """Typed nodes whose type requires `field` (its registry entry says so) and that leave it empty."""
        return [
            view
            for view in self.typed_nodes
            if field in defaults.entry(view.node).required and not getattr(view.node, field)
        ]

    @cached_property
    def _endpoints(self) -> tuple[dict, dict, dict]:
        publishers: dict[str, list[Endpoint]] = defaultdict(list)
        subscribers: dict[str, list[Endpoint]] = defaultdict(list)
        readers: dict[str, list[Endpoint]] = defaultdict(list)
        by_role = {topology.PUBLISHER: publishers, topology.SUBSCRIBER: subscribers, topology.READER: readers}
        views = {view.index: view for view in self.nodes}
        for declared in topology.declarations(self.config, defaults.node_names(self.config)):
            view = views.get(declared.index)
            if view is None or view.node.type == pb.NODE_TYPE_UNSPECIFIED:
                continue
            message_type = declared.message_type if msg_catalog.is_known(declared.message_type) else ""
            by_role[declared.role][declared.topic].append(
                Endpoint(view, declared.topic, message_type, declared.qos, declared.at, declared.implied)
            )
        return dict(publishers), dict(subscribers), dict(readers)

    @property
    def publishers(self) -> dict[str, list[Endpoint]]:
        """Resolved topic -> its publishers, in file order."""
        return self._endpoints[0]

    @property
    def subscribers(self) -> dict[str, list[Endpoint]]:
        """Resolved topic -> nodes subscribing to it as their topic_name (with their own type and QoS)."""
        return self._endpoints[1]

    @property
    def readers(self) -> dict[str, list[Endpoint]]:
        """Resolved topic -> nodes reading it through input_topics."""
        return self._endpoints[2]

    def qos_at(self, endpoint: Endpoint, policy_field: str) -> Path:
        """The path of the QoS field that applies to an endpoint when written, else of its topic field."""
        path = endpoint.at[:-1] + (policy_field,)
        return path if self.written(path) else endpoint.at

    @cached_property
    def topic_holders(self) -> list[tuple[NodeView, Node | pb.TopicDeclaration, Path]]:
        """(node, message, path) of every message with topic fields (topic_name, message_type, qos_*):
        each node, and each topic a CUSTOM node declares in `publishes` / `subscribes`."""
        holders = []
        for view in self.nodes:
            holders.append((view, view.node, view.path))
            if defaults.entry(view.node).declares_topics:
                for field in ("publishes", "subscribes"):
                    holders += [(view, topic, view.at(field, k)) for k, topic in enumerate(getattr(view.node, field))]
        return holders


def is_set(message, field: str) -> bool:
    """Whether a field holds a value: present (optional/message), non-empty (repeated), non-default (plain)."""
    descriptor = message.DESCRIPTOR.fields_by_name[field]
    if descriptor.is_repeated:
        return len(getattr(message, field)) > 0
    if descriptor.has_presence:
        return message.HasField(field)
    return getattr(message, field) != descriptor.default_value


def label_of(view: NodeView) -> str:
    """`node "camera"` for a named node, `node #3` (1-based, in file order) for an unnamed one."""
    return f'node "{view.node.name}"' if view.node.name else f"node #{view.index + 1}"


def strings_of(message, path: Path = ()):
    """(path, what, text) of every string in a message, recursively: values, list items, map keys and values."""
    for fd, value in message.ListFields():
        field_path = path + (fd.name,)
        if fd.message_type is not None and fd.message_type.GetOptions().map_entry:
            for key, item in value.items():
                yield field_path + (key,), f"{fd.name} name", key
                yield field_path + (key,), f"{fd.name} value of {key}", item
        elif fd.message_type is not None:
            items = value if fd.is_repeated else [value]
            for index, item in enumerate(items):
                yield from strings_of(item, field_path + (index,) if fd.is_repeated else field_path)
        elif fd.type == FieldDescriptor.TYPE_STRING:
            if fd.is_repeated:
                for index, item in enumerate(value):
                    yield field_path + (index,), fd.name, item
            else:
                yield field_path, fd.name, value
