"""Helpers of the bag tests: a robot of two mock arms at 50 Hz and an MCAP recorder of both, compiled by joshuac."""

from testsupport.compiled_settings import compiled_settings

ARM = "/arm/joint_states"
FOLLOWER = "/follower/joint_states"


def two_arm_recorder(output, extra: str = "") -> dict[str, dict]:
    """Settings of `arm`, `follower` and `recorder` (output_format mcap into `output`, plus `extra` fields)."""
    return compiled_settings(f'''robot_config {{
      name: "bagbot" mode: MODE_DATA_COLLECTION
      node {{ name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "{ARM}" rate_hz: 50 }}
      node {{ name: "follower" type: MOCK_ENCODER_PUBLISHER topic_name: "{FOLLOWER}" rate_hz: 50 }}
      node {{ name: "recorder" type: DATA_SUBSCRIBER topic_name: "{ARM}" input_topics: ["{FOLLOWER}"]
              output_format: "mcap" output_directory: "{output}" {extra} }}
    }}''')
