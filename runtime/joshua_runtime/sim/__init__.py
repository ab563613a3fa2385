"""MuJoCo simulation engine used in MODE_SIMULATION.

In MODE_SIMULATION joshuac starts no hardware node; one SIMULATION process (engine_node.py) stands in
for all of them, on their own topics, message types and QoS. Each hardware node type's registry entry
names the bridge that plays its part (`sim_bridge`): one module per type in bridges/, whose docstring
says what the simulated node publishes and how it reads its commands; bridge.py says what every
bridge is. Joint units are those of the real drivers: radians, rad/s, and effort as a signed fraction
of the actuator's force limit. Header stamps are the ROS clock (wall time), frame_id the node's.

Files: models/ (the built-in scenes, `builtin:so100` and `builtin:lego_bot`), model.py (loading),
engine.py (physics thread on a wall-clock schedule), cameras.py (render thread), lidar.py (ray
casts), gl_backend.py (EGL/OSMesa choice before mujoco is imported), joint_state_source.py (joint
readings as JointState), diagnostics.py (/diagnostics of simulated servos), scripted_motion.py (a
demo motion source for the actuator's command topic).

Driving the simulated arm in a demo: run scripted_motion as a CUSTOM node publishing on the
actuator's topic_name (`python -m joshua_runtime.sim.scripted_motion --topic /so100/command`), or
point a MOCK_ENCODER_PUBLISHER with the SO-100 joint_names at that topic: its sinusoids become
goals (clamped to the ranges; the arm will brush the table on the widest swings).
"""
