"""Ending the designer's worker processes (path synthesis, the run on the motor)."""
from __future__ import annotations


def stop_process(proc) -> None:
    """End a worker process now: SIGTERM, then SIGKILL for one that ignores it (stopped or stuck)."""
    if proc.is_alive():
        proc.terminate()
        proc.join(0.5)
        if proc.is_alive():
            proc.kill()
            proc.join(0.5)
