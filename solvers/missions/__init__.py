"""Built-in missions, one module each; a module defining MISSION is registered."""
