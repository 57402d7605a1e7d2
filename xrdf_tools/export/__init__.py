"""XRDF → other formats: a cuRobo robot YAML and a MoveIt SRDF."""
