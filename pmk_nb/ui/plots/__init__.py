"""Home's Plots panel: speed and turn rate, and the topic inspector."""
