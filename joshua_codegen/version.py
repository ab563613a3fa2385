"""The joshuac version written into every generated file's header."""

VERSION = "0.1.0"
