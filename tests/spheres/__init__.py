"""Tests of xrdf_tools.spheres: sphere fitting and surface distances."""
