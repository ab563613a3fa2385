"""Fast DDS Discovery Server for robots on several computers: launching it, and telling whether it answers."""
