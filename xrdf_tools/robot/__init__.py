"""A loaded robot: the URDF (or expanded xacro) as one value, its joints, tree, link geometry,
packages and kinematics."""
