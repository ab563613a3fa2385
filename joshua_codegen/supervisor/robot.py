"""Placeholder robot data; supervisor.py gets the real values of these names from joshuac."""

from typing import Any

ROBOT: dict[str, Any] = {
    "name": "example",
    "supervisor_code": "",
    "env": {"PYTHONUNBUFFERED": "1"},
    "cpp_bin_dir": "bin",
    "fastdds_profile_variable": "FASTRTPS_DEFAULT_PROFILES_FILE",
    "supervisord_group": "joshua-example",
    "stamp_file": ".joshuac-stamp",
    "model_registry": {
        "prefix": "registry:",
        "variable": "JOSHUA_MODEL_REGISTRY",
        "default_root": "~/.cache/joshua/models",
        "entry_file": "joshua_model.json",
    },
    "node_exit_codes": {"settings": 2, "data_lost": 6},
    "settings_format_version": 5,
    "processes": [],
}

SIGINT_GRACE_S = 5.0
SIGTERM_GRACE_S = 2.0
