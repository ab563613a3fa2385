"""What the compiler and the runtime share: the schema, node types, device facts and small utilities."""
