"""Tests of xrdf_tools.export and the export command."""
