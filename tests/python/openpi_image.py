#!/usr/bin/env python3
"""What openpi's LIBERO client sends for an upright RGB frame, computed with openpi-client.

Usage: openpi_image.py WIDTH HEIGHT SIZE IN.rgb OUT.rgb

IN.rgb holds the upright frame (row 0 at the top). robosuite hands LIBERO clients the frame
bottom-up (`upright[::-1]`); `examples/libero/main.py` then takes `[::-1, ::-1]` and calls
`image_tools.resize_with_pad(img, SIZE, SIZE)`. OUT.rgb receives those bytes.
"""

import sys

import numpy as np
from openpi_client import image_tools

w, h, size = (int(v) for v in sys.argv[1:4])
upright = np.fromfile(sys.argv[4], dtype=np.uint8).reshape(h, w, 3)
raw = upright[::-1]
img = np.ascontiguousarray(raw[::-1, ::-1])
out = image_tools.convert_to_uint8(image_tools.resize_with_pad(img, size, size))
np.ascontiguousarray(out).tofile(sys.argv[5])
