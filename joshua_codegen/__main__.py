"""`python -m joshua_codegen` runs the joshuac command line."""

from joshua_codegen.cli import main

main()
