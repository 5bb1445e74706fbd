"""coopnav's experiment layer: runs, fault injection, populations, metrics and figures.

One program (`scripts/coopnav <command>`) over one declarative description of the system
(`config/system.yaml`, read by `system.py`). Each command is a module with
`add_arguments(parser)` and `main(args) -> int`, registered in `cli.py`.
"""
