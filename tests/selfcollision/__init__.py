"""Tests of xrdf_tools.selfcollision: collision, the counting engine, certify, sampling,
configurations."""
