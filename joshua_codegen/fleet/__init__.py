"""Fleets: one file naming several robots, each a robot description with its own overrides and address.

load.py        a fleet file's text -> FleetDescription + source positions
check.py       every robot checked with its overrides; the fleet rules (rules/e6xx_*.py)
releases.py    one release per robot: its build, bundle, stamp and signature
ansible.py     the inventory and playbooks that roll the releases out
robot/         the scripts the playbooks run on each robot (standard library only)
"""
