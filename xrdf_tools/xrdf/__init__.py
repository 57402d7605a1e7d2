"""The XRDF format: the model, reading and writing it, its schema, shape and versions, and the
programs that read it (targets)."""
