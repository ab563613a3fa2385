"""MuJoCo simulation engine used in MODE_SIMULATION.

In MODE_SIMULATION joshuac starts no hardware node; one SIMULATION process (engine_node.py) stands in
for all of them, on their own topics, message types and QoS:

    ENCODER_PUBLISHER      JointState of joint_names at rate_hz (rad, rad/s, effort = signed fraction
                           of the actuator's force limit, as the STS3215 driver reports)
    ACTUATOR_SUBSCRIBER    JointState commands -> position-actuator goals (by name; by order when the
                           message has no names; clamped to the range); states on state_topic at rate_hz
    CAMERA_PUBLISHER       rendered frames, width x height at rate_hz: Image "rgb8", or CompressedImage
                           (JPEG) when the topic's type is CompressedImage. The model camera is the one
                           named like the node's frame_id, else simulation.camera, else the first one.
    LIDAR_PUBLISHER        LaserScan of 360 rays cast in the plane of the site named like frame_id, else
                           site "lidar" (LDS-01 geometry; 0.0 where nothing is within 0.12-3.5 m)
    OPERATIONAL_LIMIT_CALIBRATION  the model's joint ranges as `<joint>.range_min/max` in raw ticks

Files: models/so100.xml (the built-in SO-100 scene, `builtin:so100`), model.py (loading), engine.py
(physics thread on a wall-clock schedule), cameras.py (render thread), lidar.py (ray casts),
gl_backend.py (EGL/OSMesa choice before mujoco is imported), bridges.py (the ROS side of each node),
scripted_motion.py (a demo motion source for the actuator's command topic).

Driving the simulated arm in a demo: run scripted_motion as a CUSTOM node publishing on the
actuator's topic_name (`python -m joshua_runtime.sim.scripted_motion --topic /so100/command`), or
point a MOCK_ENCODER_PUBLISHER with the SO-100 joint_names at that topic: its sinusoids become
goals (clamped to the ranges; the arm will brush the table on the widest swings).
"""
