"""L3: file formats and units (TOML mechanism files, CSV tables)."""
