"""Robot descriptions (URDF) shipped with the runtime, and the model a ROBOT_STATE_PUBLISHER reads from them."""
