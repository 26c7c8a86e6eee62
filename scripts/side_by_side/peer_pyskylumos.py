#!/usr/bin/env python3
"""PySkyLumos (github.com/taciochi/pyskylumos) on the side-by-side frames.

Its README's quick start, sized to the paper's camera: 2448x2048 px of 3.45 um, a 1.8 mm
equidistant ('equi_angle') lens, Rayleigh sky at Marseille on 2022-09-23 every 30 min from
06:00 UTC; the sky's DoP and AoP as float32 (no sensor measurement). Writes nothing. On Debian's
astropy 5.2 the sky map is built as newer astropy builds it (adapt_to_old_astropy, at run time).
Usage: peer_pyskylumos.py REPO FRAMES
"""
import sys

import numpy as np


def adapt_to_old_astropy():
    """Debian 12's astropy 5.2 refuses what newer ones accept: the sky map's altitude/azimuth grid
    (H, W) in a frame whose obstime has shape (T, 1, 1) ("attribute obstime should be scalar or
    have shape (2048, 2448)"). Newer astropy broadcasts the two to (T, H, W); here the grid is
    given that shape up front (a broadcast view: no copy), so PySkyLumos computes the same arrays
    as with a newer astropy. Applied at run time, only when the original call fails; the peer's
    files are not changed."""
    import numpy as np
    from astropy.units import deg
    from astropy.coordinates import AltAz, SkyCoord
    from pyskylumos.sky_models.Rayleigh import Rayleigh

    original = Rayleigh.__init__

    def init(self, times, observation_location, altitudes, azimuths):
        try:
            original(self, times=times, observation_location=observation_location, altitudes=altitudes,
                     azimuths=azimuths)
        except ValueError as e:
            if "obstime" not in str(e):
                raise
            shape = times.shape + np.shape(altitudes)
            self._sky_map = SkyCoord(alt=np.broadcast_to(altitudes, shape) * deg,
                                     az=np.broadcast_to(azimuths, shape) * deg,
                                     frame=AltAz(obstime=times[:, None, None], location=observation_location))

    Rayleigh.__init__ = init


def main():
    repo, frames = sys.argv[1], int(sys.argv[2])
    # Offline, astropy would spend seconds failing to download IERS tables: use the bundled ones.
    from astropy.utils import iers
    iers.conf.auto_download = False
    sys.path.insert(0, repo + "/src")
    from astropy.coordinates import EarthLocation
    from astropy.time import Time
    from pyskylumos.engine import Engine
    from pyskylumos.sensor import SlicingPattern
    adapt_to_old_astropy()

    slicing = {a: SlicingPattern(start_row=r, start_column=c, step=2)
               for a, r, c in ((0, 0, 0), (45, 0, 1), (90, 1, 0), (135, 1, 1))}
    engine = Engine(sensor_pixel_size_square_micrometers=3.45, lens_conjugation_type="equi_angle",
                    number_pixels_vertical=2048, number_pixels_horizontal=2448, lens_focal_length_micrometers=1800,
                    tolerance=0.0, extinction_ratio=0.99, pixel_saturation_ratio=0.9, adc_resolution=12,
                    signal_to_noise_ratio=50, wire_grid_orientations_slicing=slicing)
    azimuths, altitudes = engine.get_initial_azimuth_altitude(altitude_min_clip=0)
    site = EarthLocation(lat=43.28699, lon=5.40336, height=60)
    # One frame per call (a one-element Time array): all 23 at once would hold 23 frames of float64
    # intermediates at a time.
    times = [Time([f"2022-09-23T{(360 + 30 * k) // 60:02d}:{(360 + 30 * k) % 60:02d}:00"]) for k in range(frames)]
    for t in times:
        parameters, names = engine.simulate_sky_polarization(sky_model="rayleigh", observation_location=site, times=t,
                                                             cie_sky_type=4, altitudes=altitudes, azimuths=azimuths,
                                                             altitude_min_clip=0.0)
        sky = dict(zip(names, parameters))
        np.asarray(sky["degree of polarization"], dtype=np.float32)
        np.asarray(sky["angle of polarization"], dtype=np.float32)


if __name__ == "__main__":
    main()
