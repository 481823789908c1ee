"""Slurm: the members' time limits (member_minutes.py); the shell scripts submit and run a cluster."""
