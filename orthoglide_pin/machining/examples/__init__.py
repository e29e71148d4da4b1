"""Example cut files shipped with the package (``*.yaml``)."""
