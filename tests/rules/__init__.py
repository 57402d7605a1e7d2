"""Tests of xrdf_tools.rules: the registry of every diagnostic id and its generated docs."""
