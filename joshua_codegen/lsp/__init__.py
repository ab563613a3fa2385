"""`joshuac lsp`: a language server for robot descriptions over stdio (diagnostics, hover, completion, ...)."""
