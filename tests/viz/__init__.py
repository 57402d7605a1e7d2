"""Tests of xrdf_tools.viz and the viz command."""
