"""Files that enter the tool: the config file (its schema, its sections, workspace samples), the spring
catalogue, the YAML/JSON readers, and the springs of an exported URDF read back."""
