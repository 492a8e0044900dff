"""Where a plan lies on Earth, when it says so: the Item geometry of a storey (else null geometry).

An IndoorGML plan is georeferenced when its ``srsName`` is a UTM CRS (WGS 84 UTM north/south,
EPSG:326zz / 327zz, or ETRS89 UTM, EPSG:258zz: within a metre of WGS 84): its coordinates are then
eastings and northings in metres and the storey's extent converts to longitude/latitude in closed
form (Krüger's series, millimetre accurate inside a zone), with no projection library. Plans in a
local frame (most) or another CRS get a null geometry, which STAC allows.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

_UTM = re.compile(r"EPSG(?::|::|/0/|/)(326|327|258)(\d\d)\b", re.IGNORECASE)
_SRS = re.compile(rb'srsName\s*=\s*"([^"]{1,200})"')
_HEAD = 256 * 1024
_A = 6378137.0  # WGS 84 semi-major axis, metres
_F = 1 / 298.257223563
_K0 = 0.9996


def plan_srs(source: Path) -> str | None:
    """The first ``srsName`` in the plan's first 256 KiB (where every exporter writes it), or None."""
    try:
        with open(source, "rb") as fh:
            match = _SRS.search(fh.read(_HEAD))
    except OSError:
        return None
    return match.group(1).decode("utf-8", "replace") if match else None


def utm_zone(srs: str | None) -> tuple[int, bool] | None:
    """(zone, northern hemisphere) of a UTM CRS name, or None for any other CRS."""
    match = _UTM.search(srs or "")
    if not match:
        return None
    zone = int(match.group(2))
    return (zone, match.group(1) != "327") if 1 <= zone <= 60 else None


def utm_to_lonlat(easting: float, northing: float, zone: int, north: bool) -> tuple[float, float]:
    """Longitude and latitude in degrees of a UTM coordinate (Krüger's series to the 3rd order)."""
    n = _F / (2 - _F)
    big_a = _A / (1 + n) * (1 + n**2 / 4 + n**4 / 64)
    beta = (n / 2 - 2 * n**2 / 3 + 37 * n**3 / 96, n**2 / 48 + n**3 / 15, 17 * n**3 / 480)
    delta = (2 * n - 2 * n**2 / 3 - 2 * n**3, 7 * n**2 / 3 - 8 * n**3 / 5, 56 * n**3 / 15)
    xi = (northing - (0.0 if north else 10_000_000.0)) / (_K0 * big_a)
    eta = (easting - 500_000.0) / (_K0 * big_a)
    xi_p = xi - sum(b * math.sin(2 * j * xi) * math.cosh(2 * j * eta) for j, b in enumerate(beta, 1))
    eta_p = eta - sum(b * math.cos(2 * j * xi) * math.sinh(2 * j * eta) for j, b in enumerate(beta, 1))
    chi = math.asin(math.sin(xi_p) / math.cosh(eta_p))
    lat = chi + sum(d * math.sin(2 * j * chi) for j, d in enumerate(delta, 1))
    lon0 = math.radians(zone * 6 - 183)
    lon = lon0 + math.atan2(math.sinh(eta_p), math.cos(xi_p))
    return math.degrees(lon), math.degrees(lat)


def footprint(srs: str | None, extent: tuple[float, float, float, float] | None) -> dict[str, object] | None:
    """GeoJSON polygon (lon/lat) of a storey's extent in a UTM plan; None when not georeferenced."""
    zone = utm_zone(srs)
    if zone is None or extent is None:
        return None
    x0, y0, x1, y1 = extent
    ring = [utm_to_lonlat(x, y, *zone) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0))]
    return {"type": "Polygon", "coordinates": [[[round(lon, 8), round(lat, 8)] for lon, lat in ring]]}


def in_crs(
    extent: tuple[float, float, float, float] | None, origin: tuple[float, float]
) -> tuple[float, float, float, float] | None:
    """A storey's extent (read from a local origin) back in the plan's CRS."""
    if extent is None:
        return None
    return (extent[0] + origin[0], extent[1] + origin[1], extent[2] + origin[0], extent[3] + origin[1])


def bbox_of(geometry: dict[str, object] | None) -> list[float] | None:
    """[west, south, east, north] of a polygon from :func:`footprint`."""
    if geometry is None:
        return None
    ring = geometry["coordinates"][0]  # type: ignore[index]
    lons, lats = [p[0] for p in ring], [p[1] for p in ring]
    return [min(lons), min(lats), max(lons), max(lats)]
