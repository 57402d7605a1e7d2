"""Every diagnostic id: the registry and the generated rules documentation."""
