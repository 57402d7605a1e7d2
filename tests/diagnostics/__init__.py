"""Tests of xrdf_tools.diagnostics: the diagnostic renderers."""
