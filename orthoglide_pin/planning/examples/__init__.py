"""Example part programs shipped with the package (G-code files, ``*.nc``)."""
