"""Tests of xrdf_tools.xrdf: the XRDF model, reader, writer, shapes and versions."""
