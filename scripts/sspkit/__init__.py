"""The co-simulation scenes as SSP 1.0 systems that third-party masters run (docs/ssp.md;
the command is scripts/ssp):

  systems.py   a scene (scripts/cosim/scenes.py) → its system: the connector FMU, the Body
               FMU(s), their parameter values and connections (one function per scene)
  archive.py   a system → dist/ssp/<scene>.ssp (SystemStructure.ssd and parameter sets written
               with pyssp-standard, validated against the SSP 1.0 schema) and the checks of an
               archive against its FMUs and its scene, made before any run
  tools.py     an archive run by libcosim, Ecos or fmpy, sampled into a master.Result
  cli.py       ./scripts/ssp SCENE --tool TOOL: run, write the CSV, print error and CPU time
"""
