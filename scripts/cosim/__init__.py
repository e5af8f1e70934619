"""A small co-simulation master for the connector FMUs (fmpy FMU2Slave) and the scenes of
docs/cosim.md with their reference answers. See master.py (the four coupling methods) and scenes.py."""
