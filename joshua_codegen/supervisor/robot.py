"""Placeholder robot data; supervisor.py gets the real values of these names from joshuac."""

from typing import Any

ROBOT: dict[str, Any] = {
    "name": "example",
    "ros_domain_id": None,
    "cpp_bin_dir": "bin",
    "fastdds_profile": "fastdds_profile.xml",
    "fastdds_profile_variable": "FASTRTPS_DEFAULT_PROFILES_FILE",
    "supervisord_group": "joshua-example",
    "processes": [],
}

SIGINT_GRACE_S = 5.0
SIGTERM_GRACE_S = 2.0
