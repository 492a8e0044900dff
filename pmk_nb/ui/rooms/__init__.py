"""Home's rooms by name: You are in, Go to a room (favourites, recent), the route on the map."""
