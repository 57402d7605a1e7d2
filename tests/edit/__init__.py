"""Tests of xrdf_tools.edit and the edit command."""
