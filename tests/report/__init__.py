"""Tests of xrdf_tools.report and the report command."""
