"""Tests of the xrdf CLI as a whole: options, messages, pinned outputs, process boundaries,
fuzzing."""
