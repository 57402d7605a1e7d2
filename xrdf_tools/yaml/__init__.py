"""YAML with source positions: loading, the node tree, limits, and the shape check for foreign
YAML. Inside this package ``import yaml`` is PyYAML (absolute imports); this package is
``xrdf_tools.yaml``."""
