"""Home's Fleet panel (issue 26): several chairs on one page, their markers, goals parked with them."""
