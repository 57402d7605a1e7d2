"""Tests of xrdf_tools.robot: the URDF reader and checks, kinematics, link geometry, inspect."""
