"""The joshuac compiler: .pbtxt robot descriptions to checked, reproducible artifacts."""
