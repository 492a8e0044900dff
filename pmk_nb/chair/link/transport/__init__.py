"""The link's socket: a roslibpy ``Ros`` on a private loop (``ros``), its factories, TLS, rosbridge auth,
the probe, the state watchdog, one blocking service call, the publishers and the Stop's side channel.
``framework`` is the one place that picks roslibpy's transport (asyncio unless Twisted came first).
"""
