"""Runtime library imported by joshuac-generated node entrypoints."""
