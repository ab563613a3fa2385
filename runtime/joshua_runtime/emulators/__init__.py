"""Protocol-level device emulators served on pseudo-terminals (`joshua-emulate`)."""
