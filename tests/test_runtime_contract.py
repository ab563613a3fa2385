"""The compiler and the runtime agree: every node type runs, and what the checker allows exists."""

import importlib

from joshua_codegen import defaults
from joshua_core.schema import robot_config_pb2 as pb
from joshua_runtime import entrypoint
from joshua_runtime.sim import gl_backend, model


def test_every_python_node_type_and_the_simulation_engine_have_a_runtime_class():
    python_types = {name for name in pb.NodeType.keys() if name not in ("NODE_TYPE_UNSPECIFIED", "CUSTOM")}
    assert set(entrypoint.NODE_CLASSES) == python_types | {"SIMULATION"}
    for target in entrypoint.NODE_CLASSES.values():
        module_name, class_name = target.split(":")
        spec = importlib.util.find_spec(module_name)
        assert spec is not None, module_name
        assert f"class {class_name}(" in open(spec.origin).read()


def test_checker_accepts_exactly_the_built_in_models_and_gl_backends_the_runtime_has():
    assert set(defaults.BUILTIN_MODELS) == set(model.BUILTIN_MODELS)
    assert defaults.BUILTIN_PREFIX == model.BUILTIN_PREFIX
    assert set(defaults.GL_BACKENDS) == set(gl_backend.GL_BACKENDS)
