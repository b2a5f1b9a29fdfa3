"""L3: derived quantities on solved states (gait metrics, transmission angles, dead centres)."""
