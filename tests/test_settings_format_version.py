"""FORMAT_VERSION moves with node_settings.proto: a changed settings contract without a new version fails here.

A runtime refuses settings of another format version (exit code 2), so a robot never runs a node whose
settings it would misread. That holds only if every change of the contract raises the version: this test
keeps the fingerprint of the compiled NodeSettings schema each version was released with.
"""

import hashlib

from google.protobuf import descriptor_pb2

from joshua_core.schema import node_settings_pb2
from joshua_core.settings import FORMAT_VERSION

# The fingerprint of node_settings.proto's compiled schema (comments do not count) for the current version.
FINGERPRINTS = {5: "adffe74714bd336a"}


def fingerprint() -> str:
    compiled = descriptor_pb2.FileDescriptorProto()
    node_settings_pb2.DESCRIPTOR.CopyToProto(compiled)
    return hashlib.sha256(compiled.SerializeToString(deterministic=True)).hexdigest()[:16]


def test_the_settings_contract_is_the_one_its_format_version_was_given_for():
    assert FINGERPRINTS.get(FORMAT_VERSION) == fingerprint(), (
        f"node_settings.proto changed (fingerprint {fingerprint()}) under FORMAT_VERSION {FORMAT_VERSION}: raise "
        "FORMAT_VERSION in core/joshua_core/settings.py, record the new fingerprint here and run `make generate`"
    )
