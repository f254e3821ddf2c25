"""The robot's camera and the observation pipeline of Fig. 2 B-C.

The paper (Sec. II-C): "The raw camera image is simply cropped and color-thresholded. After
downsizing (32x10 pixels) and a grayscale conversion, it is then directly used as input to the
network (Fig. 2C)." This module holds the camera's intrinsics, the fixed crop rectangle (the
white dotted rectangle of Fig. 2B), the red threshold, and the function that turns a rendered
RGB frame into the network's input ``I``.

Choices the paper leaves open (all fields of :class:`CameraConfig`):

* Frame size 160x120 and Nao's top-camera field of view (47.6 deg vertical; 60.9 deg
  horizontal follows from the 4:3 frame).
* The crop: the full frame width and a band of 60 rows around the height at which the
  landmark appears. The 160x60 band is resized to 32x10, i.e. every input pixel averages a
  5x6 block of the band.
* The threshold: the landmark's red in HSV (hue within 10 deg of red, saturation and value
  high), so shading on the landmark's faces does not matter and nothing else in the room
  passes.
* Grayscale: the binary red mask is resized by area averaging, so an input pixel is the
  fraction of its block covered by the landmark (float32 in [0, 1]). The paper's grayscale
  conversion of the thresholded colour image is replaced by this coverage fraction (named
  deviation; the information is the same: where the landmark is).
"""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np

from docking.validate import check_int, check_int_tuple, check_real, normalise


@dataclasses.dataclass(frozen=True)
class CameraConfig:
    """Intrinsics of the robot's head camera and the observation pipeline.

    Attributes:
      width: Rendered frame width in pixels (160 x 120 is 4:3, like Nao's camera).
      height: Rendered frame height in pixels.
      fovy_deg: Vertical field of view; Nao's top camera has 47.6 deg (horizontal 60.9 deg
        follows from the aspect ratio).
      tilt_deg: Downward pitch of the optical axis.
      crop: The fixed input rectangle (x0, y0, x1, y1) in frame pixels, the white dotted
        rectangle of Fig. 2B.
      input_shape: (rows, cols) of the network input: 32x10 pixels (Sec. II-A).
      hue_tol: Half-width of the accepted hue band around red, in OpenCV hue units (0..180).
      min_saturation: Lower bound of a red pixel's saturation (0..255).
      min_value: Lower bound of a red pixel's value, its brightness (0..255).
    """

    width: int = 160
    height: int = 120
    fovy_deg: float = 47.6
    tilt_deg: float = 5.0
    crop: tuple[int, int, int, int] = (0, 16, 160, 76)
    input_shape: tuple[int, int] = (10, 32)
    hue_tol: int = 10
    min_saturation: int = 120
    min_value: int = 60

    def __post_init__(self):
        owner = "CameraConfig"
        width = check_int(owner, "width", self.width, lo=1, hi=4096)
        height = check_int(owner, "height", self.height, lo=1, hi=4096)
        fovy = check_real(
            owner, "fovy_deg", self.fovy_deg, lo=0, hi=180, lo_open=True, hi_open=True
        )
        tilt = check_real(owner, "tilt_deg", self.tilt_deg, lo=-90, hi=90)
        crop = check_int_tuple(owner, "crop", self.crop, 4, lo=0)
        x0, y0, x1, y1 = crop
        if not (x0 < x1 <= width and y0 < y1 <= height):
            raise ValueError(
                f"CameraConfig.crop must satisfy 0 <= x0 < x1 <= width and 0 <= y0 < y1 <= "
                f"height, got {crop} for a {width}x{height} frame"
            )
        input_shape = check_int_tuple(owner, "input_shape", self.input_shape, 2, lo=1)
        if input_shape[0] > y1 - y0 or input_shape[1] > x1 - x0:
            raise ValueError(
                f"CameraConfig.input_shape (rows, cols) must fit the crop's {y1 - y0} rows and "
                f"{x1 - x0} columns (it averages blocks of the crop), got {input_shape}"
            )
        normalise(
            self,
            width=width,
            height=height,
            fovy_deg=fovy,
            tilt_deg=tilt,
            crop=crop,
            input_shape=input_shape,
            hue_tol=check_int(owner, "hue_tol", self.hue_tol, lo=0, hi=90),
            min_saturation=check_int(owner, "min_saturation", self.min_saturation, lo=0, hi=255),
            min_value=check_int(owner, "min_value", self.min_value, lo=0, hi=255),
        )

    @property
    def fovx_deg(self) -> float:
        """Horizontal field of view implied by ``fovy_deg`` and the frame's aspect ratio."""
        half = math.tan(np.radians(self.fovy_deg) / 2) * self.width / self.height
        return float(np.degrees(2 * math.atan(half)))

    @property
    def focal_px(self) -> float:
        """Focal length in pixels (square pixels)."""
        return float(self.height / 2 / math.tan(np.radians(self.fovy_deg) / 2))


def red_mask(frame: np.ndarray, config: CameraConfig) -> np.ndarray:
    """Colour-threshold an RGB frame: uint8 mask, 255 where the pixel is the landmark's red."""
    hsv = cv2.cvtColor(np.ascontiguousarray(frame), cv2.COLOR_RGB2HSV)
    lo_s, lo_v = config.min_saturation, config.min_value
    low = cv2.inRange(hsv, (0, lo_s, lo_v), (config.hue_tol, 255, 255))
    high = cv2.inRange(hsv, (180 - config.hue_tol, lo_s, lo_v), (180, 255, 255))
    return cv2.bitwise_or(low, high)


def preprocess(frame: np.ndarray, config: CameraConfig) -> np.ndarray:
    """Turn a rendered RGB frame into the network input ``I`` (Fig. 2C).

    Crop the fixed rectangle, threshold the landmark's red, resize to 32x10 by area
    averaging. Returns float32 of shape ``config.input_shape`` with values in [0, 1].
    """
    if frame.shape != (config.height, config.width, 3):
        raise ValueError(
            f"frame must have shape {(config.height, config.width, 3)}, got {frame.shape}"
        )
    x0, y0, x1, y1 = config.crop
    return preprocess_band(frame[y0:y1, x0:x1], config)


def preprocess_band(band: np.ndarray, config: CameraConfig) -> np.ndarray:
    """:func:`preprocess` of the crop rectangle alone (``band`` is the frame's crop, as the
    robot's camera renders it): threshold the landmark's red, resize to 32x10."""
    x0, y0, x1, y1 = config.crop
    if band.shape != (y1 - y0, x1 - x0, 3):
        raise ValueError(f"band must have shape {(y1 - y0, x1 - x0, 3)}, got {band.shape}")
    mask = red_mask(band, config)
    rows, cols = config.input_shape
    small = cv2.resize(mask, (cols, rows), interpolation=cv2.INTER_AREA)
    return small.astype(np.float32) * np.float32(1.0 / 255.0)
