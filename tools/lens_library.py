#!/usr/bin/env python3
"""Writes the lens library, lens-data/library/*.json, from the prescriptions
transcribed below, each with its source.

Run from the repository root after `cargo build --release -p lens-cli`:

    python3 tools/lens_library.py

For each lens: the surfaces as the source gives them (radius, thickness,
index nd and Abbe number vd as a model glass, the clear semi-diameter where
the source gives one), the film at the paraxial focus for infinity (the
source's back focus is printed beside it), and the stop sized so that the
paraxial f-number is the source's (`lens convert --f-number`) unless the
source gives the stop's diameter. The stated focal length and f-number are
what crates/lens/tests/library.rs checks the files against.

Sources and licences: patent tables are facts published by the patent
offices. Transcriptions used: the Photons to Photos Optical Bench data files
(photonstophotos.net, cited per lens), the lentil polynomial-optics lens
database (github.com/zpelgrims/lentil, polynomial-optics/database/
lenses.json, MIT licence; its housing radii are lentil's and used here as
clear semi-diameters; and its polynomial-optics/lenses/nikon-zoom.fx, W. J.
Smith's table of a Nikon 80-200 mm zoom), ray-optics' cell phone example
(github.com/mjhoptics/ray-optics, docs/source/examples/Cell_Phone_lens,
BSD-3-Clause) and its models of two Nikon zooms' wide ends (src/rayoptics/
optical/tests/*.roa: curvatures, gaps, model glasses, asphere terms), the
crayg renderer's lens files (github.com/Latios96/crayg, resources/
lensfiles: numbers only, for the rows the Optical Bench excerpt lacked),
github.com/seb-hoch/pbrtmtf's transcriptions of W. J. Smith, Modern
Lens Design (1992) pp. 304-305 (numbers only), and an open-source C++
optical-preset table ("opsys") of four Optical Bench files (numbers only:
vertex positions, clear radii, nd and vd), and the Lens Visualizer project's
data files (lensvisualizer.pages.dev; numbers only: radii, gaps, nd, vd,
asphere terms, and its estimated clear radii, which each source names).
Only numbers are taken, no code.
"""

import json
import os
import re
import subprocess
import sys
import tempfile

LENS = os.path.join("target", "release", "lens")
OUT = os.path.join("lens-data", "library")

# A surface: (radius or None for a plane, thickness, nd or None for air (or
# a catalogue glass's name, "SCHOTT:N-LAK9"), vd, semi-diameter or None),
# then optionally either a dict of the format's fields (asphere terms,
# {"aspheric": [...]}, or {"stop": True} for a curved stop) or ray-optics'
# (ec = 1 + k, odd-power coefficients r^1...). The row marked "stop" is a
# plane stop.
STOP = "stop"


def glass(nd, vd):
    return {"nd": nd, "vd": vd}


def zoom_80_200(d5, d10, d13):
    """The Nikon 80-200 mm f/2.8 zoom of Smith's Modern Lens Design (2nd
    ed., pp. 527-528, Fig. 20.3) at one zoom position: the three gaps that
    move (d5, d10, d13 of the table)."""
    D5, D10, D13 = d5, d10, d13
    return [
    (148.570, 5.0, 1.564, 60.7, 32.2),
    (-479.279, 0.357, None, None, 32.2),
    (192.855, 6.286, 1.589, 61.2, 31.0),
    (-134.999, 2.214, 1.805, 25.4, 31.0),
    (-874.852, D5, None, None, 30.5),
    (-285.712, 3.893, 1.755, 27.5, 19.0),
    (-44.764, 1.036, 1.517, 64.2, 19.0),
    (59.357, 5.357, None, None, 19.0),
    (-45.071, 1.250, 1.589, 61.2, 16.0),
    (166.174, D10, None, None, 16.0),
    (164.284, 5.000, 1.658, 57.3, 15.0),
    (-33.928, 1.036, 1.795, 28.4, 15.0),
    (-85.047, D13, None, None, 15.0),
    (30.464, 5.357, 1.670, 57.5, 16.7),
    (162.202, 3.071, None, None, 16.3),
    (-374.997, 1.786, 1.805, 25.4, 15.2),
    (259.105, 17.857, None, None, 14.5),
    (STOP, 18.000, None, None, 9.4),
    (-17.214, 1.714, 1.713, 53.8, 10.5),
    (-30.230, 0.286, None, None, 11.5),
    (62.857, 3.071, 1.773, 49.7, 12.6),
    (-466.815, 28.611, None, None, 12.6),
]


# The zoom's table has the lengths of an 80-200 mm lens times 0.715: its
# short end's paraxial EFL is 57.206145081111984 mm (the long end's
# 143.0763893631863, ratio 2.501 as the source's 2.5). Scaled so that the
# short end is the stated 80 mm; the long end is then 200.085 mm.
ZOOM_SCALE = 80.0 / 57.206145081111984
ZOOM_SOURCE = (
    "Nikon JP S53-131852 (80-200 mm F/2.8, zoom ratio 2.5), as W. J. Smith, Modern Lens Design, 2nd ed., "
    "pp. 527-528 (Fig. 20.3) gives it, transcribed in the lentil lens database (github.com/zpelgrims/lentil, "
    "polynomial-optics/lenses/nikon-zoom.fx, MIT; its semi-apertures, glasses by nd and vd, the iris's place, "
    "and the three moving gaps d5/d10/d13 = 1.86/36.928/16.55 at the short end and 48.678/1.536/5.133 at the long "
    "end); the table's lengths are those of the 80-200 mm lens times 0.715 (its ends' EFLs 57.206 and 143.076 mm): "
    "every length scaled by 80/57.206145 so that the short end is the stated 80 mm, the long end then 200.085 mm; "
    "the stop sized for F 2.8 at each end (the two stops agree within 0.05%, as a constant-aperture zoom's must)"
)


LIBRARY = [
    {
        "file": "fast-50mm-f1.4-us3552829.json",
        "name": "50 mm f/1.4 double Gauss (US 3,552,829 Example 1)",
        "source": "US 3,552,829 (1971) Example 1, as transcribed in the Photons to Photos Optical Bench "
        "(US3552829_Example01P): f = 50, F/1.4, angle of view 46.7 degrees, Bf 36.5; clear diameters and the stop's "
        "(24.1 mm) as the file gives them: the stop gives f/1.43 (at f/1.4 the marginal ray would need surfaces 4 "
        "and 5 "
        "to cross)",
        "efl": 50.0,
        "f_number": 1.4,
        "stated": "Optical Bench file: Focal Length 50, F-Number 1.4",
        "stop_given": True,
        "rows": [
            (56.655, 5.24, 1.815, 45.2, 38.50 / 2),
            (600.0, 0.565, None, None, 38.50 / 2),
            (25.68, 6.56, 1.694, 54.6, 33.50 / 2),
            (51.875, 0.80, None, None, 28.716 / 2),
            (84.60, 2.255, 1.63003, 35.4, 34.00 / 2),
            (17.295, 5.865, None, None, 24.50 / 2),
            (STOP, 5.565, None, None, 24.10 / 2),
            (-19.475, 2.855, 1.7918, 25.9, 24.00 / 2),
            (246.02, 6.185, 1.8004, 42.7, 31.00 / 2),
            (-35.965, 0.095, None, None, 31.00 / 2),
            (-125.895, 4.05, 1.8004, 42.7, 31.50 / 2),
            (-37.625, 0.095, None, None, 31.50 / 2),
            (198.13, 4.05, 1.71615, 53.7, 31.50 / 2),
            (-63.025, 36.5, None, None, 31.50 / 2),
        ],
    },
    {
        "file": "phone-5.6mm-f3.5-us7535658.json",
        "name": "Cell phone camera lens 5.6 mm f/3.5, five aspheric elements (US 7,535,658)",
        "source": "US 7,535,658 (2009), as entered in ray-optics' cell phone example (docs/source/examples/"
        "Cell_Phone_lens): radii, thicknesses, nd/vd, conics (ray-optics' ec = 1 + k) and the odd-asphere terms "
        "r^3..r^10 as given; clear semi-diameters as ray-optics traces them; efl 5.555 mm and f/3.5 as it lists them",
        "efl": 5.555,
        "f_number": 3.5,
        "stated": "ray-optics' first-order listing of this model: efl 5.555, f/# 3.5",
        "stop_given": False,
        "rows": [
            (STOP, 0.0, None, None, 0.79358),
            (1.962, 1.19, 1.471, 76.6, 0.938, 2.153, [0, 0, -1.895e-2, 2.426e-2, -5.123e-2, 8.371e-4, 7.850e-3, 4.091e-3, -7.732e-3, -4.265e-3]),
            (33.398, 0.93, None, None, 1.0837, 40.18, [0, 0, -4.966e-3, -1.434e-2, -6.139e-3, -9.284e-5, 6.438e-3, -5.72e-3, -2.385e-2, 1.108e-2]),
            (-2.182, 0.75, 1.603, 27.5, 1.1338, 2.105, [0, 0, -4.388e-2, -2.555e-2, 5.16e-2, -4.307e-2, -2.831e-2, 3.162e-2, 4.630e-2, -4.877e-2]),
            (-6.367, 0.1, None, None, 1.539, 3.382, [0, 0, -1.131e-1, -7.863e-2, 1.094e-1, 6.228e-3, -2.216e-2, -5.89e-3, 4.123e-3, 1.041e-3]),
            (5.694, 0.89, 1.510, 56.2, 1.8254, -221.1, [0, 0, -7.876e-2, 7.02e-2, 1.575e-3, -9.958e-3, -7.322e-3, 6.914e-4, 2.54e-3, -7.65e-4]),
            (9.192, 0.16, None, None, 2.3978, 0.9331, [0, 0, 9.694e-3, -2.516e-3, -3.606e-3, -2.497e-4, -6.84e-4, -1.414e-4, 2.932e-4, -7.284e-5]),
            (1.674, 0.85, 1.510, 56.2, 2.482, -7.617, [0, 0, 7.429e-2, -6.933e-2, -5.811e-3, 2.396e-3, 2.100e-3, -3.119e-4, -5.552e-5, 7.969e-6]),
            (1.509, 0.70, None, None, 2.9297, -2.707, [0, 0, 1.767e-3, -4.652e-2, 1.625e-2, -3.522e-3, -7.106e-4, 3.825e-4, 6.271e-5, -2.631e-5]),
            (None, 0.40, 1.516, 64.1, 3.3067),
            (None, 0.64, None, None, 3.4058),
        ],
    },
    {
        "file": "primoplan-f1.9-de1387593.json",
        "automatic_field_deg": 20.4,
        "name": "Meyer Primoplan f/1.9, f = 100 (the 58 mm f/1.9's design)",
        "source": "Meyer-Optik Goerlitz Primoplan (1936), patent table normalised to f = 100 as transcribed in the "
        "lentil lens database (entry 10, 'Primoplan 58mm f1.9', patent number as lentil gives it: DE1387593); "
        "clear semi-diameters made to pass the full stop on the axis and at the field given in the library's notes "
        "(tools/lens_library.py: lens convert --clear-apertures)",
        "efl": 100.0,
        "f_number": 1.9,
        "stated": "lentil entry 10: focal-length-mm-patent 100; notes 'Primoplan 58mm f1.9'",
        "stop_given": False,
        "rows": [
            (70.2, 10.9, 1.66, 51.1, 34.0),
            (1450.1, 0.7, None, None, 34.0),
            (43.3, 3.6, 1.648, 33.8, 34.0),
            (26.9, 10.9, 1.623, 57.1, 25.0),
            (54.0, 5.1, None, None, 25.0),
            (STOP, 5.1, None, None, 25.0),
            (-193.0, 3.6, 1.687, 31.3, 25.25),
            (32.9, 11.2, None, None, 25.25),
            (82.8, 23.6, 1.621, 53.2, 27.5),
            (-52.8, 51.26, None, None, 27.5),
        ],
    },
    {
        "file": "takumar-35mm-f2-us3506336.json",
        "automatic_field_deg": 31.7,
        "name": "Asahi SMC Takumar 35 mm f/2 design (US 3,506,336), f = 100",
        "source": "US 3,506,336 (1970, Asahi), example normalised to f = 100, as transcribed in the lentil lens "
        "database (entry 7, 'SMC Takumar 35mm f2.0')",
        "efl": 100.0,
        "f_number": 2.0,
        "stated": "lentil entry 7: focal-length-mm-patent 100; notes 'SMC Takumar 35mm f2.0'",
        "stop_given": False,
        "rows": [
            (450.0, 7.0, 1.58913, 61.2, 35.0),
            (80.137, 47.0, None, None, 30.0),
            (-2300.0, 10.0, 1.762, 40.3, 25.0),
            (-292.234, 2.0, None, None, 25.0),
            (95.7, 18.0, 1.77252, 49.6, 25.0),
            (-707.468, 1.0, None, None, 25.0),
            (80.0, 8.0, 1.53172, 48.9, 25.0),
            (84.488, 9.0, None, None, 25.0),
            (STOP, 9.0, None, None, 25.0),
            (-91.5, 6.5, 1.74077, 27.7, 25.0),
            (98.025, 8.0, None, None, 25.0),
            (1000.0, 4.0, 1.834, 37.2, 25.0),
            (71.0, 19.0, 1.77252, 49.6, 25.0),
            (-89.354, 0.5, None, None, 25.0),
            (-600.0, 10.0, 1.77252, 49.6, 25.0),
            (-110.648, 103.26, None, None, 25.0),
        ],
    },
    {
        "file": "flektagon-35mm-f2.8-de953471.json",
        "automatic_field_deg": 31.7,
        "name": "Zeiss Flektagon 35 mm f/2.8 design (DE 953 471), f = 100",
        "source": "DE 953 471 (1956, Carl Zeiss Jena), example normalised to f = 100, as transcribed in the lentil "
        "lens database (entry 9, 'Flektagon 35mm f2.8')",
        "efl": 100.0,
        "f_number": 2.8,
        "stated": "lentil entry 9: focal-length-mm-patent 100; notes 'Flektagon 35mm f2.8'",
        "stop_given": False,
        "rows": [
            (116.42, 6.89, 1.6244, 60.3, 40.0),
            (65.01, 73.06, None, None, 35.0),
            (67.32, 8.13, 1.6051, 42.2, 20.0),
            (561.28, 1.24, None, None, 20.0),
            (30.55, 9.65, 1.6583, 51.0, 17.5),
            (68.68, 3.31, 1.6645, 35.9, 17.5),
            (21.89, 9.37, None, None, 17.5),
            (STOP, 11.03, None, None, 17.5),
            (-26.36, 3.31, 1.7588, 26.7, 16.5),
            (-37.41, 0.28, None, None, 16.5),
            (-222.9, 2.76, 1.6204, 36.3, 16.5),
            (183.48, 8.13, 1.6224, 60.3, 16.5),
            (-37.84, 99.54, None, None, 16.5),
        ],
    },
    {
        "file": "angenieux-double-gauss-us2701982.json",
        "automatic_field_deg": 20.0,
        "name": "Angenieux large-aperture double Gauss (US 2,701,982), f = 100",
        "source": "US 2,701,982 (1955, P. Angenieux), example normalised to f = 100, as transcribed in the lentil "
        "lens database (entry 1, 'large aperture six element objective'); clear semi-diameters are lentil's "
        "the source states no f-number: the stop is lentil's housing radius (25.5 mm)",
        "efl": 100.0,
        "f_number": None,
        "stated": "lentil entry 1: focal-length-mm-patent 100 (no f-number given)",
        "stop_given": True,
        "rows": [
            (164.13, 10.99, 1.6751, 32.3, 54),
            (559.2, 0.23, None, None, 54),
            (100.12, 11.45, 1.6689, 46.7, 51),
            (213.54, 0.23, None, None, 51),
            (58.04, 22.95, 1.6913, 53.8, 41),
            (2551.1, 2.58, 1.6751, 32.3, 41),
            (32.39, 15.66, None, None, 27),
            (STOP, 15.0, None, None, 25.5),
            (-40.42, 2.74, 1.6992, 30.2, 25),
            (192.98, 27.92, 1.6204, 60.2, 36),
            (-55.53, 0.23, None, None, 36),
            (192.98, 7.98, 1.6913, 53.8, 35),
            (-225.3, 0.23, None, None, 35),
            (175.09, 8.48, 1.6913, 53.8, 35),
            (-203.55, 55.742, None, None, 35),
        ],
    },
    {
        "file": "petzval-kodak-us2500046.json",
        "automatic_field_deg": 10.0,
        "name": "Kodak Petzval projection lens (US 2,500,046), f = 100",
        "source": "US 2,500,046 (1950, Eastman Kodak), 'Petzval type lens, f=100mm', as transcribed in the lentil "
        "lens database (entry 14); the stop (18 mm) is lentil's housing radius; "
        "the source states no f-number",
        "efl": 100.0,
        "f_number": None,
        "stated": "lentil entry 14: focal-length-mm-patent 100, notes 'Petzval type lens, f=100mm'",
        "stop_given": True,
        "rows": [
            (70.97, 15.0, 1.523, 58.6, 23.0),
            (-56.79, 4.5, 1.617, 38.5, 23.0),
            (None, 24.0, None, None, 23.0),
            (STOP, 25.3, None, None, 18.0),
            (119.91, 3.8, 1.649, 33.8, 15.0),
            (40.87, 0.9, None, None, 15.0),
            (46.87, 7.4, 1.697, 56.1, 15.0),
            (-282.05, 56.47, None, None, 15.0),
        ],
    },
    {
        "file": "takumar-us3451745.json",
        "automatic_field_deg": 23.4,
        "name": "Asahi Takumar, Biotar type (US 3,451,745), f = 100",
        "source": "US 3,451,745 (1969, Asahi), example normalised to f = 100, as transcribed in the lentil lens "
        "database (entry 6, 'Based on the Biotar design'); the stop (26.4 mm) is lentil's "
        "the source as transcribed states no f-number",
        "efl": 100.0,
        "f_number": None,
        "stated": "lentil entry 6: focal-length-mm-patent 100",
        "stop_given": True,
        "rows": [
            (110.0, 10.0, 1.80416, 46.6, 42.0),
            (588.748, 0.2, None, None, 42.0),
            (51.6, 14.5, 1.79446, 45.4, 36.0),
            (100.426, 3.5, None, None, 36.0),
            (119.0, 3.0, 1.71736, 29.5, 32.4),
            (32.792, 16.26, None, None, 26.4),
            (STOP, 16.25, None, None, 26.4),
            (-36.5, 2.0, 1.68893, 31.1, 26.4),
            (131.5, 20.0, 1.77252, 49.6, 32.4),
            (-56.806, 0.2, None, None, 32.4),
            (-160.0, 8.5, 1.77252, 49.6, 32.4),
            (-74.352, 0.2, None, None, 32.4),
            (122.0, 9.5, 1.77252, 49.6, 32.4),
            (2092.573, 63.31, None, None, 32.0),
        ],
    },
    {
        "file": "master-prime-100mm-t1.3-us20070236805.json",
        "name": "Cine prime 100 mm T1.3 with an asphere (US 2007/0236805 Example 4, ~ARRI/Zeiss Master Prime 100 mm)",
        "source": "US 2007/0236805 (2007, Carl Zeiss) Example 4, as transcribed in the Photons to Photos Optical Bench "
        "(US2007-0236805_Example04: Focal Length 99.80, F-Number 1.24, angle of view 17.81 degrees, Bf 40.123; the "
        "focus gaps d9 = 14.959, d13 = 16.343, d22 = 1.00 for infinity); its clear diameters halved; the surfaces "
        "after the stop "
        "and the even-asphere coefficients A4..A14 of surface 11 (conic 0) as the crayg renderer's transcription of "
        "the same file gives them (github.com/Latios96/crayg, resources/lensfiles/ArriZeissMasterPrime.fx, which "
        "numbers them a2..a12); the stop sized for F 1.24",
        "efl": 99.80,
        "f_number": 1.24,
        "stated": "Optical Bench file: Focal Length 99.80, F-Number 1.24",
        "stop_given": False,
        "rows": [
            (-1883.6, 4.7, 1.54075, 47.23, 89.06 / 2),
            (101.45, 3.14, None, None, 83.94 / 2),
            (127.72, 15.68, 1.61803, 63.33, 88.56 / 2),
            (-281.84, 0.2, None, None, 88.56 / 2),
            (66.355, 14.78, 1.43876, 94.99, 84.46 / 2),
            (202.42, 0.1, None, None, 77.98 / 2),
            (113.83, 4.85, 1.80527, 25.42, 79.16 / 2),
            (89.125, 14.959, None, None, 72.83 / 2),
            (52.33, 14.19, 1.75704, 47.82, 65.12 / 2),
            (381.29, 7.54, None, None, 61.13 / 2),
            (-230.02127, 2.8, 1.61344, 44.29, 53.56 / 2,
             {"aspheric": [0.0, 8.669e-07, 9.230e-11, 2.783e-14, -9.209e-16, 1.576e-18, -8.587e-22]}),
            (29.64, 16.343, None, None, 42.30 / 2),
            (STOP, 18.938, None, None, 41.0351 / 2),
            (-27.582, 2.97, 1.61344, 44.29, 39.42 / 2),
            (285.92, 12.52, 1.69104, 54.82, 48.44 / 2),
            (-41.867, 0.55, None, None, 50.48 / 2),
            (188.36, 8.18, 1.69104, 54.82, 50.48 / 2),
            (-76.076, 0.1, None, None, 50.48 / 2),
            (110.6, 10.69, 1.60303, 65.44, 46.52 / 2),
            (-46.305, 2.8, 1.65416, 39.63, 45.30 / 2),
            (153.99, 1.0, None, None, 48.74 / 2),
            (73.918, 4.22, 1.49702, 81.54, 39.96 / 2),
            (158.49, 40.123, None, None, 39.96 / 2),
        ],
    },
    {
        "file": "double-gauss-100mm-f1.35-us2601805.json",
        "name": "Double Gauss f = 100 f/1.35, 13 degrees (Lowenthal, US 2,601,805; Smith p. 305)",
        "source": "W. J. Smith, Modern Lens Design (1992) p. 305: F/1.35 13 deg, US 2,601,805 (Lowenthal); EFL 100.4, "
        "BFL 55.07, NA 0.3676 (f/1.36), semi-apertures and glasses (LaF2, SK55, FN11, SF8) by the book's nd and vd, "
        "as transcribed in github.com/seb-hoch/pbrtmtf (p305_dgauss_lens.py); the stop sized for the book's NA",
        "efl": 100.4,
        "f_number": 1.36,
        "stated": "Smith p. 305: EFL 100.4, NA 0.3676",
        "stop_given": False,
        "rows": [
            (85.5, 11.6, 1.744, 44.7, 38.0),
            (408.33, 1.5, None, None, 38.0),
            (40.35, 17.0, 1.620, 60.1, 33.0),
            (156.05, 3.5, 1.621, 36.2, 33.0),
            (25.05, 13.7, None, None, 22.0),
            (STOP, 8.3, None, None, 21.3),
            (-36.8, 3.5, 1.689, 31.2, 22.0),
            (55.0, 23.0, 1.744, 44.7, 26.0),
            (-51.5, 1.0, None, None, 26.0),
            (123.5, 17.0, 1.744, 44.7, 26.0),
            (-204.96, 55.066, None, None, 26.0),
        ],
    },
    {
        "file": "tronnier-double-gauss-50mm-f2-us2673491.json",
        "name": "Double Gauss 50 mm f/2, 22 degrees (Tronnier, US 2,673,491), the patent's glasses",
        "source": "US 2,673,491 (A. W. Tronnier, Voigtlander, 1954), the table at f = 1.0, 1:2, back focus "
        "p0' = 0.71436: radii and thicknesses times 50 (as pbrt-v4's dgauss.50mm.dat prints them), the stop where "
        "the patent splits the middle air space (b1 = 5.466, b2 = 4.741 at f = 50; pbrt's file has 5.705 and "
        "4.5), and the patent's indices and Abbe numbers (1.67125/47.1, 1.69842/30.1, 1.60266/38.4, "
        "1.65953/57.0, 1.71740/48.1; pbrt's file rounds them, 1.65953 to 1.658, which moves its focal length to "
        "50.36); clear semi-diameters pbrt's housing radii (the patent gives none); the stop sized for 1:2",
        "efl": 50.0,
        "f_number": 2.0,
        "stated": "US 2,673,491: f = 1.0 (times 50), 1:2, p0' = 0.71436 f",
        "stop_given": False,
        "rows": [
            (29.475, 3.76, 1.67125, 47.1, 12.6),
            (84.83, 0.12, None, None, 12.6),
            (19.275, 4.025, 1.67125, 47.1, 11.5),
            (40.77, 3.275, 1.69842, 30.1, 11.5),
            (12.75, 5.466, None, None, 9.0),
            (STOP, 4.741, None, None, 8.55),
            (-14.495, 1.18, 1.60266, 38.4, 8.5),
            (40.77, 6.065, 1.65953, 57.0, 10.0),
            (-20.385, 0.19, None, None, 10.0),
            (437.065, 3.22, 1.71740, 48.1, 10.0),
            (-39.73, 35.718, None, None, 10.0),
        ],
    },
    {
        "file": "double-gauss-100mm-f1.25-us2771006.json",
        "name": "Double Gauss f = 100 f/1.25, 12 degrees (Werfel, US 2,771,006; Smith p. 304)",
        "source": "W. J. Smith, Modern Lens Design (1992) p. 304: F/1.25 12 deg, US 2,771,006 (Werfel); EFL 100.1, "
        "BFL 56.42, NA 0.3992 (f/1.25), semi-apertures and glasses (LaF3, BaF9, LF2, SF14, LaF2) by the book's nd and "
        "vd, as transcribed in github.com/seb-hoch/pbrtmtf (p304_dgauss_lens.py); the stop sized for the book's NA",
        "efl": 100.1,
        "f_number": 1.25,
        "stated": "Smith p. 304: EFL 100.1, NA 0.3992",
        "stop_given": False,
        "rows": [
            (93.32, 11.32, 1.717, 48.0, 40.0),
            (358.29, 0.4, None, None, 40.0),
            (46.32, 20.0, 1.643, 48.0, 36.0),
            (None, 2.0, 1.589, 40.9, 36.0),
            (28.68, 14.0, None, None, 24.5),
            (STOP, 10.0, None, None, 24.3),
            (-41.32, 6.0, 1.762, 26.5, 24.0),
            (60.8, 22.0, 1.744, 44.7, 30.0),
            (-55.0, 13.0, None, None, 30.0),
            (90.2, 16.0, 1.717, 48.0, 28.0),
            (-212.58, 56.424, None, None, 28.0),
        ],
    },
    {
        "file": "nikkor-z-14-30mm-f4-wide-jp2019008031.json",
        "name": "Wide-angle zoom at 14.42 mm f/4, four aspheres (JP 2019-008031 Example 1 at its wide end, ~Nikon "
            "Nikkor Z 14-30 mm f/4 S)",
        "source": "JP 2019-008031 (Nikon) Example 1 at the wide-angle end (f = 14.42, F 4.0, half field 57.68 degrees; "
        "the zoom gaps d8 = 28.616, d14 = 7.483 and the back focus 21.36 of that end), as ray-optics' model of it "
        "gives "
        "it (github.com/mjhoptics/ray-optics, src/rayoptics/optical/tests/Nikon Nikkor Z 14-30mm f-4 S.roa, "
        "BSD-3-Clause: radii from its curvatures, gaps, nd and vd, clear semi-diameters, and the even-asphere "
        "coefficients of surfaces 2, 4, 17 and 26 with their conics); the stop sized for F 4.0",
        "efl": 14.42,
        "f_number": 4.0,
        "stated": "JP 2019-008031 Example 1, wide end: f = 14.42, F 4.0 (ray-optics' model: its spec sheet)",
        "stop_given": False,
        "rows": [
            (190.7535, 3.0, 1.6937, 53.32, 29.285),
            (18.8098, 9.5, None, None, 22.485,
             {"conic": -1.0, "aspheric": [0.0, -1.33157e-05, -3.07345e-08, 6.9126e-11, -3.76684e-14]}),
            (51.563, 2.9, 1.6937, 53.32, 19.205),
            (22.702, 9.7, None, None, 14.475,
             {"conic": -1.0, "aspheric": [0.0, 3.67009e-05, 1.37031e-07, -5.20756e-10, 3.14884e-12, -5.6153e-15]}),
            (-71.0651, 1.9, 1.49782, 82.57, 15.05),
            (44.4835, 0.1, None, None, 15.05),
            (32.608, 4.5, 1.90265, 35.73, 15.05),
            (296.5863, 28.616, None, None, 15.05),
            (63.0604, 2.0, 1.59349, 67.0, 9.04),
            (499.8755, 0.1, None, None, 9.04),
            (24.0057, 1.2, 1.883, 40.66, 9.605),
            (13.347, 4.5, 1.56883, 56.0, 8.54),
            (333.9818, 2.5, None, None, 8.54),
            (STOP, 7.483, None, None, 5.6335),
            (36.3784, 1.1, 1.816, 46.59, 8.59),
            (14.0097, 4.71, 1.51612, 64.08, 8.42),
            (61.0448, 0.2, None, None, 8.42,
             {"aspheric": [0.0, 1.75905e-05, -6.64635e-08, 2.26551e-10, -4.40763e-12]}),
            (27.9719, 3.15, 1.49782, 82.57, 8.55),
            (-75.3921, 0.25, None, None, 8.55),
            (91.9654, 3.05, 1.49782, 82.57, 8.915),
            (-29.3923, 1.579, None, None, 8.915),
            (72.093, 1.0, 1.795, 45.31, 9.065),
            (20.9929, 5.766, None, None, 9.065),
            (-538.2301, 4.8, 1.49782, 82.57, 10.935),
            (-20.1257, 0.1, None, None, 10.935),
            (-38.9341, 1.4, 1.76546, 46.75, 11.06,
             {"conic": -1.0, "aspheric": [0.0, -2.67902e-05, -3.34364e-08, -1.13765e-10, -1.88017e-13]}),
            (154.832, 21.36, None, None, 11.815),
        ],
    },
    {
        "file": "kit-zoom-18.5mm-f3.5-wide-us7277232.json",
        "name": "Kit zoom at 18.5 mm f/3.56, hybrid asphere (US 7,277,232 Example 4 at its wide end, ~Nikon AF-S "
            "DX 18-55 mm f/3.5-5.6G ED II)",
        "source": "US 7,277,232 (Nikon) Example 4 at the wide-angle end (f = 18.5, F 3.56, image height 14.2, the zoom "
        "gap d5 = 44.0936 and the back focus 41.84285 of that end), as ray-optics' model of it gives it "
        "(github.com/mjhoptics/ray-optics, src/rayoptics/optical/tests/US007277232_Example04P.roa, BSD-3-Clause: "
        "radii from its curvatures, gaps, nd and vd, clear semi-diameters; its zero-thickness dummy plane after the "
        "last lens dropped). The asphere of surface 3 (the resin layer's rear of the hybrid front element) has "
        "kappa = 0.0375 (conic -0.9625) and five coefficients, read here as Nikon writes them, C3 |r|^3, C4 r^4, "
        "C6 r^6, C8 r^8, C10 r^10 (the model stores them as r^3..r^7, which leaves the corner 3.5 times less sharp); "
        "the stop sized for F 3.56",
        "efl": 18.5,
        "f_number": 3.56,
        "stated": "US 7,277,232 Example 4, wide end: f = 18.5, F 3.56 (ray-optics' model: its spec sheet)",
        "stop_given": False,
        "rows": [
            (181.0591, 2.0, 1.7725, 49.61, 20.31),
            (17.2, 0.2, 1.55389, 38.09, 14.995),
            (12.763, 12.25, None, None, 14.76,
             {"conic": -0.9625,
              "odd_aspheric": [0.0, 0.0, 7.9879e-06, 3.0368e-06, 0.0, -2.1516e-08, 0.0, 5.2594e-11, 0.0, -2.5891e-13]}),
            (33.8814, 2.8, 1.86074, 23.06, 15.23),
            (65.8125, 44.0936, None, None, 15.23),
            (42.5378, 2.6, 1.497, 81.61, 9.18),
            (-94.5446, 1.8, None, None, 9.18),
            (STOP, 2.0, None, None, 7.8985),
            (24.2385, 4.0, 1.5168, 64.1, 9.14),
            (-35.8523, 0.8, 1.7725, 49.61, 8.83),
            (67.243, 11.2, None, None, 8.83),
            (54.1555, 0.8, 1.834, 37.17, 8.83),
            (15.5723, 4.5, 1.5168, 64.1, 8.83),
            (-35.4635, 41.84285, None, None, 8.83),
        ],
    },
    {
        "file": "zoom-80-200mm-f2.8-at-80mm-jp53131852.json",
        "name": "Zoom 80-200 mm f/2.8 at its short end, 80 mm (Nikon JP S53-131852; Smith, Modern Lens Design, "
            "Fig. 20.3)",
        "source": ZOOM_SOURCE + "; this file: the short end",
        "efl": 80.0,
        "f_number": 2.8,
        "stated": "Smith, Modern Lens Design 2nd ed. Fig. 20.3: EFL 80-200, F/2.8 (the short end sets the scale: "
            "its EFL is checked by construction)",
        "stop_given": False,
        "scale": ZOOM_SCALE,
        "rows": zoom_80_200(1.86, 36.928, 16.55),
    },
    {
        "file": "zoom-80-200mm-f2.8-at-200mm-jp53131852.json",
        "name": "Zoom 80-200 mm f/2.8 at its long end, 200 mm (Nikon JP S53-131852; Smith, Modern Lens Design, "
            "Fig. 20.3)",
        "source": ZOOM_SOURCE + "; this file: the long end",
        "efl": 200.0,
        "f_number": 2.8,
        "stated": "Smith, Modern Lens Design 2nd ed. Fig. 20.3: EFL 80-200, F/2.8",
        "stop_given": False,
        "scale": ZOOM_SCALE,
        "rows": zoom_80_200(48.678, 1.536, 5.133),
    },
    {
        "file": "triplet-50mm-f4-geiser-sasian.json",
        "automatic_field_deg": 20.0,
        "name": "Triplet 50 mm f/4, 20 degrees, Schott glasses (Geiser; J. Sasian's OPTI 517 course)",
        "source": "The triplet J. Sasian uses in his Lens Design course OPTI 517 (University of Arizona), attributed "
        "to Geiser: EFL 50, f/4 (entrance pupil 12.5 mm), 20 degrees half field, N-LAK9 and N-SF5 from the "
        "Schott catalogue, the stop on the flint's front surface, as ray-optics' example gives it "
        "(github.com/mjhoptics/ray-optics, docs/source/examples/SasianTriplet, BSD-3-Clause: efl 50, f/# 4); "
        "the stop sized for f/4",
        "efl": 50.0,
        "f_number": 4.0,
        "stated": "Sasian's triplet (ray-optics' example): efl 50, f/# 4, entrance pupil 12.5 mm",
        "stop_given": False,
        "rows": [
            (23.713, 4.831, "SCHOTT:N-LAK9", None, None),
            (7331.288, 5.86, None, None, None),
            (-24.456, 0.975, "SCHOTT:N-SF5", None, None, {"stop": True}),
            (21.896, 4.822, None, None, None),
            (86.759, 3.127, "SCHOTT:N-LAK9", None, None),
            (-20.4942, 41.2365, None, None, None),
        ],
    },
    {
        "file": "nikkor-28mm-f2.8s-us5917663.json",
        "name": "28 mm f/2.8 retrofocus wide angle (US 5,917,663 Example 2, ~Nikon AI Nikkor 28 mm f/2.8S)",
        "source": "US 5,917,663 (Nikon) Example 2, as the Photons to Photos Optical Bench gives it "
            "(US5917663_Example02: "
        "focal length 28.61, F-number 2.89; its clear diameters halved), numbers as transcribed (numbers only) in "
        "an open-source optical-preset table (the C++ 'opsys' presets: vertex positions, clear radii, nd and vd); "
        "the stop sized for F 2.89",
        "efl": 28.61,
        "f_number": 2.89,
        "stated": "Optical Bench file: focal length 28.61, F-number 2.89",
        "stop_given": False,
        "rows": [
            (60.5, 3.5, 1.67003, 47.07, 20.535),
            (118.3, 0.1, None, None, 20.535),
            (36.9, 1.5, 1.5168, 64.1, 17.335),
            (15.4, 4.0, None, None, 13.0),
            (28.2, 1.5, 1.5168, 64.1, 14.005),
            (15.13, 14.4, None, None, 12.02),
            (28.6, 4.4, 1.66755, 41.96, 7.75),
            (None, 1.35, None, None, 7.75),
            (None, 4.0, 1.62041, 60.14, 10.275),
            (-33.97, 1.0, None, None, 10.275),
            (STOP, 4.3, None, None, 6.915),
            (-20.8, 2.55, 1.7552, 27.61, 7.94),
            (53.18, 1.0, None, None, 7.0),
            (-46.001, 3.1, 1.67025, 57.53, 7.0),
            (-17.9, 0.1, None, None, 9.07),
            (109.097, 3.5, 1.67025, 57.53, 10.555),
            (-34.8, 38.98, None, None, 10.555),
        ],
    },
    {
        "file": "fisheye-16mm-f2.8-us5434713.json",
        "name": "16 mm f/2.8 full-frame fisheye (US 5,434,713 Example 2, ~Nikon AI AF Fisheye-Nikkor 16 mm f/2.8D)",
        "source": "US 5,434,713 (Nikon) Example 2, as the Photons to Photos Optical Bench gives it "
            "(US5434713_Example02: "
        "focal length 15.6686, F-number 2.8; its clear diameters halved; the last plate a filter), numbers as "
        "transcribed (numbers only) in an open-source optical-preset table (the C++ 'opsys' presets: vertex "
        "positions, clear radii, nd and vd); "
        "the stop sized for F 2.8",
        "efl": 15.6686,
        "f_number": 2.8,
        "stated": "Optical Bench file: focal length 15.6686, F-number 2.8 (the file's paraxial EFL is 15.731, +0.40%)",
        "stop_given": False,
        "rows": [
            (69.258, 1.7, 1.64, 60.0, 26.305),
            (15.165, 10.25, None, None, 14.65),
            (130.305, 1.7, 1.62041, 60.1, 15.135),
            (14.794, 4.0, None, None, 11.41),
            (32.412, 8.0, 1.62588, 35.7, 10.135),
            (-15.298, 9.0, 1.79668, 45.4, 10.135),
            (-38.75, 7.05, None, None, 7.24),
            (STOP, 3.93, None, None, 7.1785),
            (-81.004, 1.2, 1.58144, 40.8, 7.7),
            (24.002, 5.0, 1.51823, 58.9, 8.305),
            (-20.608, 0.89, None, None, 8.305),
            (46.733, 5.5, 1.5186, 70.0, 9.815),
            (-19.219, 1.3, 1.7847, 26.1, 9.815),
            (-40.706, 0.85, None, None, 10.83),
            (None, 1.2, 1.5168, 64.1, 11.605),
            (None, 38.55, None, None, 11.605),
        ],
    },
    {
        "file": "nikkor-s-50mm-f1.4-us3560079.json",
        "name": "50 mm f/1.4 double Gauss (US 3,560,079 Example 1, ~Nikon Nikkor-S Auto 50 mm f/1.4)",
        "source": "US 3,560,079 (Nikon) Example 1, as the Photons to Photos Optical Bench gives it "
            "(US3560079_Example01: "
        "focal length 50, F-number 1.4; its clear diameters and stop diameter, 23.379 mm, halved), numbers as "
        "transcribed (numbers only) in an open-source optical-preset table (the C++ 'opsys' presets: vertex "
        "positions, clear radii, nd and vd); its "
        "stop gives f/1.45 and its clear apertures pass at most f/1.41, so f/1.4 is the nominal figure: tested on "
        "the EFL only",
        "efl": 50.0,
        "f_number": None,
        "stated": "Optical Bench file: focal length 50, F-number 1.4 nominal (its stop: f/1.45)",
        "stop_given": True,
        "rows": [
            (38.275, 6.3, 1.66446, 35.9, 19.24),
            (125.265, 0.095, None, None, 19.24),
            (28.68, 8.43, 1.6935, 53.4, 17.26),
            (620.205, 1.645, 1.64831, 33.8, 17.26),
            (16.2, 7.82, None, None, 11.97),
            (STOP, 8.46, None, None, 11.6895),
            (-14.46, 2.035, 1.69895, 30.1, 11.475),
            (-193.8, 8.235, 1.713, 53.9, 15.36),
            (-22.675, 0.195, None, None, 15.36),
            (-116.28, 4.165, 1.6779, 55.5, 16.375),
            (-31.785, 0.095, None, None, 16.375),
            (77.52, 3.1, 1.713, 53.9, 17.26),
            (-843.87, 37.5, None, None, 17.26),
        ],
    },
    {
        "file": "nikkor-85mm-f1.8-us4812027.json",
        "name": "85 mm f/1.8 portrait lens (US 4,812,027 Example 1, ~Nikon AI AF Nikkor 85 mm f/1.8S)",
        "source": "US 4,812,027 (Nikon, M. Yanagisawa) Example 1: f = 85, F/1.8, 2 omega = 28 degrees, six elements, "
        "at the patent's scale, transcribed (numbers only) in the Lens Visualizer project's data file for this "
        "lens (lensvisualizer.pages.dev), with its clear radii (that file's estimates: the patent gives none); the "
        "patent tabulates no stop: its place, 9.4 mm into the 27.633 mm air space "
        "after surface 6, is that file's reading of the patent's figure; the stop sized for F 1.8",
        "efl": 85.0,
        "f_number": 1.8,
        "stated": "US 4,812,027 Ex. 1 (via Lens Visualizer): f = 85, F/1.8",
        "stop_given": False,
        "rows": [
            (42.082, 8.8, 1.76684, 46.76, 24.0),
            (214.882, 0.2, None, None, 23.0),
            (32.583, 7.8, 1.72, 50.28, 20.8),
            (61.173, 1.6, None, None, 18.4),
            (112.4, 3.2, 1.7847, 26.07, 18.1),
            (21.331, 9.4, None, None, 14.8),
            (STOP, 18.233, None, None, 13.7161),
            (-24.8, 2.4, 1.62588, 35.64, 13.8),
            (-104.881, 2.0, None, None, 14.8),
            (-69.065, 5.0, 1.6935, 53.76, 15.0),
            (-30.448, 0.2, None, None, 15.5),
            (87.287, 5.0, 1.76684, 46.76, 16.4),
            (-125.021, 38.208, None, None, 16.4),
        ],
    },
    {
        "file": "canon-35mm-f2-is-aspheric-us20150205081.json",
        "name": "35 mm f/2 with an asphere (US 2015/0205081 Example 1, ~Canon EF 35 mm f/2 IS USM)",
        "source": "US 2015/0205081 (Canon, A. Mizuma) Example 1: f = 34.49, F 2.05, 2 omega = 64.2 degrees, ten "
            "elements, "
        "the stop the patent's surface 12, one even asphere (surface 18: K = 0, A4, A6, A8), transcribed (numbers "
        "only) in the Lens Visualizer project's data file for this lens (lensvisualizer.pages.dev), with its clear "
        "radii (that file's estimates: the patent gives none); the stop sized "
        "for F 2.05",
        "efl": 34.49,
        "f_number": 2.05,
        "stated": "US 2015/0205081 Ex. 1 (via Lens Visualizer): f = 34.49, F 2.05",
        "stop_given": False,
        "rows": [
            (107.841, 2.0, 1.48749, 70.2, 25.2),
            (36.325, 3.37, None, None, 25.2),
            (60.9, 4.53, 1.7725, 49.6, 21),
            (253.393, 9.91, None, None, 21),
            (478.362, 1.5, 1.58144, 40.8, 15.2),
            (19.063, 9.05, None, None, 12.6),
            (32.422, 4.55, 1.883, 40.8, 14.1),
            (-98.623, 3.98, None, None, 14.1),
            (-54.46, 3.64, 1.883, 40.8, 13),
            (-20.463, 1.0, 1.61293, 37.0, 13),
            (63.422, 3.24, None, None, 11.2),
            (STOP, 2.68, None, None, 9.767426625218043),
            (69.18, 2.29, 1.6968, 55.5, 10.5),
            (-128.073, 5.46, None, None, 10.5),
            (-15.746, 0.95, 1.738, 32.3, 10.5),
            (-131.434, 4.37, 1.59522, 67.7, 12.2),
            (-18.862, 0.2, None, None, 12.4),
            (-91.82, 3.48, 1.58313, 59.4, 11.9, {"aspheric": [0.0, -1.49529e-05, 4.91763e-09, -4.11063e-11]}),
            (-23.365, 38.3, None, None, 11.9),
        ],
    },
    {
        "file": "micro-nikkor-105mm-f2.8-macro-us7218457.json",
        "name": "Macro 105 mm f/2.8, floating focus to 1:1, at infinity (US 7,218,457 Example 3, ~Nikon AF-S VR "
            "Micro-Nikkor 105 mm f/2.8G)",
        "source": "US 7,218,457 (Nikon, Sensui) Example 3 at infinity focus: f = 104.00, F 2.88, fourteen "
            "elements, the "
        "floating-focus gaps D8 = 3.0, D13 = 21.449, D14 = 14.484, D20 = 2.0 and the back focus 53.12017 of infinity "
        "(at 1:1 the file gives 21.289, 3.16, 0.0, 16.484, 52.48113), surface 15 a dummy plane of the patent's, "
        "transcribed (numbers only) in the Lens Visualizer project's data file for this lens "
        "(lensvisualizer.pages.dev), with its clear radii (that file's estimates: the patent gives none); the stop "
        "sized for F 2.88",
        "efl": 104.0,
        "f_number": 2.88,
        "stated": "US 7,218,457 Ex. 3 (via Lens Visualizer): f = 104.00, F 2.88",
        "stop_given": False,
        "rows": [
            (135.481, 4.8268, 1.7725, 49.61, 29.0),
            (-190.5454, 0.2, None, None, 27.5),
            (49.725, 5.0443, 1.61272, 58.75, 27.5),
            (328.1282, 3.2512, None, None, 23.0),
            (-301.4048, 1.3, 1.71736, 29.52, 22.5),
            (36.6648, 0.2601, None, None, 21.5),
            (39.1876, 5.0203, 1.7725, 49.61, 15.0),
            (None, 3.0, None, None, 18.0),
            (-184.4593, 1.1, 1.58267, 46.43, 17.5),
            (27.3895, 4.0524, None, None, 14.0),
            (-173.3863, 1.2519, 1.53172, 48.87, 12.0),
            (26.3938, 4.0212, 1.80518, 25.43, 15.0),
            (89.6909, 21.449, None, None, 14.5),
            (STOP, 14.484, None, None, 12.9),
            (None, 2.4681, None, None, 14.0),
            (114.4253, 3.0007, 1.497, 81.61, 14.5),
            (-114.4253, 0.15, None, None, 14.0),
            (52.1409, 1.1283, 1.84666, 23.78, 14.0),
            (26.564, 6.9913, 1.62041, 60.29, 13.5),
            (-77.9021, 2.0, None, None, 13.0),
            (754.4676, 1.1, 1.8061, 40.94, 13.0),
            (21.4197, 4.805, 1.80518, 25.43, 12.5),
            (37.4268, 8.821, None, None, 12.0),
            (-27.164, 1.1, 1.51823, 58.96, 14.0),
            (-51.22, 0.15, None, None, 14.5),
            (88.6706, 4.9019, 1.7859, 44.2, 15.0),
            (-88.6706, 53.12017, None, None, 15.5),
        ],
    },
    {
        "file": "sony-planar-50mm-f1.4-aspheric-us20140071331.json",
        "name": "50 mm f/1.4 with two aspheres (US 2014/0071331 Example 4, ~Sony Planar T* 50 mm f/1.4 ZA SSM)",
        "source": "US 2014/0071331 (Sony, Katou) Example 4: f = 51.5, F/1.45, 2 omega = 46.8 degrees, eight "
            "elements, the "
        "stop the patent's surface 8, even aspheres on surfaces 5 (K = 0) and 14 (K = -1.6554), terms A4..A10, "
        "transcribed (numbers only) in the Lens Visualizer project's data file for this lens "
        "(lensvisualizer.pages.dev), with its clear radii (that file's estimates: the patent gives none); the stop "
        "sized for F 1.45",
        "efl": 51.5,
        "f_number": 1.45,
        "stated": "US 2014/0071331 Ex. 4 (via Lens Visualizer): f = 51.5, F/1.45",
        "stop_given": False,
        "rows": [
            (60.388, 6.04, 1.834805, 42.7, 24.0),
            (-214.645, 0.37, None, None, 18.5),
            (-156.603, 1.3, 1.592703, 35.5, 18.2),
            (35.0, 3.0, None, None, 18.0),
            (28.547, 7.17, 1.851348, 40.1, 18.0, {"aspheric": [0.0, -1.05e-06, -6.57e-10, -1.73e-12, 4.21e-15]}),
            (-503.384, 1.2, 1.61293, 37.0, 16.1),
            (25.007, 14.509, None, None, 15.8),
            (STOP, 6.333, None, None, 13.0),
            (-21.841, 2.8, 1.64769, 33.8, 13.2),
            (30.673, 7.94, 1.883, 40.8, 13.6),
            (-47.908, 0.2, None, None, 14.3),
            (247.339, 2.13, 1.69895, 30.1, 14.3),
            (38.671, 7.0, 1.768015, 49.2, 14.1),
            (-50.305, 36.098, None, None, 14.5,
             {"conic": -1.6554, "aspheric": [0.0, 5.1e-06, -9.77e-10, 2.06e-11, -8.11e-15]}),
        ],
    },
]


def surfaces(rows, scale=1.0):
    """The format's surfaces from the rows, every length times `scale`."""
    out = []
    for row in rows:
        r, t, nd, vd, sd = row[:5]
        if scale != 1.0:
            if len(row) > 5:
                raise SystemExit("scaling an asphere's coefficients is not written")
            r = r if r in (None, STOP) else round(r * scale, 6)
            t = round(t * scale, 6)
            sd = None if sd is None else sd * scale
        s = {}
        if r == STOP:
            s["stop"] = True
        elif r is not None:
            s["radius"] = r
        s["thickness"] = t
        if nd is not None:
            # a catalogue glass by name, or a model glass of nd and vd
            s["glass"] = nd if isinstance(nd, str) else glass(nd, vd)
        if sd is not None:
            s["semi_diameter"] = round(sd, 6)
        if len(row) == 6:
            s.update(row[5])  # the asphere's fields as the format names them
        elif len(row) > 5:
            ec, coefs = row[5], row[6]
            k = round(ec - 1.0, 10)
            if k != 0:
                s["conic"] = k
            while coefs and coefs[-1] == 0:
                coefs = coefs[:-1]
            s["odd_aspheric"] = coefs
        out.append(s)
    return out


def lens(*args):
    run = subprocess.run([LENS, *args], capture_output=True, text=True)
    if run.returncode != 0:
        raise SystemExit(f"lens {' '.join(args)}: {run.stderr}")
    return run.stdout


LIMIT = re.compile(r"surface (\d+) \(semi-diameter [^)]*\) limits the on-axis bundle")
CROSS = re.compile(r"surfaces (\d+) and (\d+) cross inside their common aperture")


def uncross(spec, path):
    """Narrows the semi-diameters of neighbouring surfaces that cross (a
    housing radius larger than the two surfaces allow) by 3% steps until
    they do not; returns the surfaces changed (1-based)."""
    changed = set()
    for _ in range(200):
        with open(path, "w") as f:
            json.dump(spec, f)
        run = subprocess.run([LENS, "validate", path], capture_output=True, text=True)
        pairs = CROSS.findall(run.stdout)
        if not pairs:
            return sorted(changed)
        for a, b in pairs:
            for i in (int(a), int(b)):
                s = spec["surfaces"][i - 1]
                if "semi_diameter" in s and not s.get("stop"):
                    s["semi_diameter"] = round(s["semi_diameter"] * 0.97, 4)
                    changed.add(i)
    raise SystemExit(f"{spec['name']}: surfaces still cross")


def main():
    os.makedirs(OUT, exist_ok=True)
    for entry in LIBRARY:
        spec = {
            "name": entry["name"],
            "source": entry["source"],
            "units": "mm",
            "surfaces": surfaces(entry["rows"], entry.get("scale", 1.0)),
        }
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "lens.json")
            auto = entry.get("automatic_field_deg")
            if auto is not None:
                # the source gives no clear apertures: only the stop's
                for surf in spec["surfaces"]:
                    if not surf.get("stop"):
                        surf.pop("semi_diameter", None)
                    elif not entry["stop_given"]:
                        surf["semi_diameter"] = 1.0  # sized for the f-number below
            narrowed = [] if auto is not None else uncross(spec, path)
            if narrowed:
                spec["source"] += (
                    "; semi-diameters of surfaces " + ", ".join(map(str, narrowed))
                    + " narrowed from the housing radii until neighbouring surfaces do not cross"
                )
            with open(path, "w") as f:
                json.dump(spec, f)
            info = json.loads(lens("info", path, "--json"))
            given_back_focus = spec["surfaces"][-1]["thickness"]
            # the film at the paraxial focus for infinity
            spec["surfaces"][-1]["thickness"] = round(info["bfl"], 6)
            with open(path, "w") as f:
                json.dump(spec, f)
            target = os.path.join(OUT, entry["file"])
            if auto is not None:
                # the largest field, from the notes' down in 10% steps, whose
                # full-stop bundle the lens passes without its surfaces'
                # rims crossing (beyond it a design vignettes by intent)
                sized = os.path.join(tmp, "sized.json")
                field = auto
                for _ in range(30):
                    args = [LENS, "convert", path, "--clear-apertures", f"{field:.2f}", "-o", sized]
                    if entry["f_number"] is not None and not entry["stop_given"]:
                        args += ["--f-number", str(entry["f_number"])]
                    if subprocess.run(args, capture_output=True, text=True).returncode == 0:
                        break
                    field *= 0.9
                else:
                    raise SystemExit(f"{entry['file']}: no field passes")
                data = json.loads(open(sized).read())
                data["source"] += (
                    f"; clear semi-diameters pass the full stop on the axis and at {field:.1f} degrees"
                    + (f" (at {auto} degrees the rims would cross: the design vignettes there)" if field < auto else "")
                )
                text = json.dumps(data)
            elif entry["f_number"] is not None and not entry["stop_given"]:
                sized = os.path.join(tmp, "sized.json")
                widened = set()
                for _ in range(100):
                    run = subprocess.run(
                        [LENS, "convert", path, "--f-number", str(entry["f_number"]), "-o", sized],
                        capture_output=True,
                        text=True,
                    )
                    if run.returncode == 0:
                        break
                    m = LIMIT.search(run.stderr)
                    if not m:
                        raise SystemExit(f"{entry['file']}: {run.stderr}")
                    k = int(m.group(1))
                    s = spec["surfaces"][k - 1]
                    s["semi_diameter"] = round(s["semi_diameter"] * 1.03, 4)
                    widened.add(k)
                    with open(path, "w") as f:
                        json.dump(spec, f)
                else:
                    raise SystemExit(f"{entry['file']}: cannot reach f/{entry['f_number']}")
                if widened:
                    spec["source"] += (
                        "; semi-diameters of surfaces " + ", ".join(map(str, sorted(widened)))
                        + f" widened from the housing radii to pass the f/{entry['f_number']} axial bundle"
                    )
                    with open(path, "w") as f:
                        json.dump(spec, f)
                    lens("convert", path, "--f-number", str(entry["f_number"]), "-o", sized)
                text = open(sized).read()
            else:
                text = lens("convert", path)
            data = json.loads(text)
        with open(target, "w") as f:
            json.dump(data, f, indent=2)
            f.write("\n")
        info = json.loads(lens("info", target, "--json"))
        print(f"{entry['file']:44s} efl {info['efl']:9.4f} (stated {entry['efl']}, "
              f"{100 * (info['efl'] / entry['efl'] - 1):+.2f}%)  f/{info['f_number']:.3f} "
              f"(stated {entry['f_number']})  bfl {info['bfl']:.3f} (source {given_back_focus})")


if __name__ == "__main__":
    sys.exit(main())
