"""Tests of xrdf_tools.util: the input reader and output writer, numbers, graphs, rotations, XML."""
