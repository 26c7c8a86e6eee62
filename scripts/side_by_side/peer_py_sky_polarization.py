#!/usr/bin/env python3
"""py-sky-polarization (github.com/ThomasKronland/py-sky-polarization) on the side-by-side frames.

Its own API, as its main.py uses it: a DoFP camera of 2448x2048 px of 3.45 um behind a 1.8 mm
equidistant ('r2') lens, the sun from its SunEphemeris (astropy), and simulate_rayleigh_sky's AoP
and DoLP images, kept as float32. Writes nothing. Usage: peer_py_sky_polarization.py REPO FRAMES
"""
import sys

import numpy as np


def main():
    repo, frames = sys.argv[1], int(sys.argv[2])
    # Offline, astropy would spend seconds failing to download IERS tables: use the bundled ones.
    from astropy.utils import iers
    iers.conf.auto_download = False
    sys.path.insert(0, repo)
    from Camera_Package import DoFPCamera, DoFPSensor, Lens
    import Polarization_Simulation_Package.polarizationSimulation as simulation
    from Sun_Ephemeris_Package import SunEphemeris

    cam = DoFPCamera(DoFPSensor(3.45, (2048, 2448), "bayer"), Lens(1.8, "r2"), (1024, 1224))
    for k in range(frames):
        minutes = 6 * 60 + 30 * k
        sun = SunEphemeris(date="2022-09-23", hour_utc=minutes // 60, minute_utc=minutes % 60, second_utc=0,
                           latitude=43.28699, longitude=5.40336)
        azimuth, elevation = sun.get_sun_horizontal_coordinates()
        aop, dolp = simulation.simulate_rayleigh_sky(cam, float(elevation), float(azimuth), 1.0)
        aop, dolp = np.asarray(aop, dtype=np.float32), np.asarray(dolp, dtype=np.float32)
        assert aop.shape == dolp.shape


if __name__ == "__main__":
    main()
