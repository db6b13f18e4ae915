"""Files that enter and leave the tool: the config schema and the URDF and MuJoCo exports."""
