"""Self-collision: sphere sets and distances, the counting engine, sampling, configurations and
certification."""
