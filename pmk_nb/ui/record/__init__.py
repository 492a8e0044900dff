"""Home's Record panel: recording topics to MCAP, and download links for files."""
