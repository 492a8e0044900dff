"""The chair: profiles, the rosbridge link, SFTP transfer, map reload and deploy.

``profiles`` (validated chair settings and the profile store), ``link/`` (rosbridge via roslibpy),
``messages`` (ROS message shapes both ROS versions use), ``ssh`` + ``transfer`` (SFTP with verified
host keys), ``reload`` (the three map reload services) and ``deploy`` (upload, reload, confirm).
Submodules are imported on use, so that `pmk info` never pays for roslibpy or paramiko.
"""
