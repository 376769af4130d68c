"""Vehicle meshes (GLB) and their table, shipped inside the installed package."""
