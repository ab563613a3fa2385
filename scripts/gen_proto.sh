#!/usr/bin/env bash
# Regenerates core/joshua_core/schema/*_pb2.py from proto/joshua/v1/*.proto (pass an output dir to write elsewhere).
set -euo pipefail
out="${1:-core/joshua_core/schema}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python -m grpc_tools.protoc -Iproto --python_out="$tmp" --pyi_out="$tmp" proto/joshua/v1/*.proto
mkdir -p "$out"
cp "$tmp"/joshua/v1/*_pb2.py "$tmp"/joshua/v1/*_pb2.pyi "$out"/
