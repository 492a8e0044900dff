"""Command-line sub-commands for the converter and maps folder."""
