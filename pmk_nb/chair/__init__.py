"""pmk_nb.chair"""
