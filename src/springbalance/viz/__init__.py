"""Pictures of a design: the Meshcat scene, its local server and the headless-browser check."""
