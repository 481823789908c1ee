"""A pull-off at another speed: the overlay that sets the intruder's velocity
and scales every time given in travel (series and snapshot intervals, the
displacement window, the free time, the check interval, the duration) by
V_scene / V, so that a run samples the same travel per record at any speed.
Used by make accuracy (its V points) and make params (its pull-speed sweep)."""


def intruder_speed(pulloff: dict) -> float:
    """The pull-off scene's intruder speed (m/s)."""
    return next(b["velocity"][1] for b in pulloff["body"] if b["name"] == "intruder")


def speed_overlay(pulloff: dict, v: float) -> dict:
    """Overlay tables for the pull-off scene `pulloff` run at v (m/s)."""
    f = intruder_speed(pulloff) / v
    out, stop = pulloff["output"], pulloff["stop"]
    return {"time": {"duration": pulloff["time"]["duration"] * f},
            "stop": {k: stop[k] * f for k in ("free_time", "check_interval") if k in stop},
            "output": {k: out[k] * f for k in ("series_interval", "snapshot_interval", "displacement_window") if k in out},
            "body": [{"name": "intruder", "velocity": [0.0, v]}]}
