"""Home's destination: tap to set a goal, its heading, status and Cancel."""
