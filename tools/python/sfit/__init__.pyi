# SPDX-License-Identifier: MIT
# Type hints of the sfit package (the runtime is sfit/__init__.py over the
# compiled sfit._sfit). Arrays in: any real array-like, float32 inside.
# Arrays out: float64 ndarrays holding float32 values.
import os
from typing import Any, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
library_version: str
MIN_SAMPLES: int

ArrayLike = npt.ArrayLike
Vec3 = npt.NDArray[np.float64]
Mat3 = npt.NDArray[np.float64]
Mode = Literal["auto", "sphere", "planar"]
Kind = Literal["cap", "arc"]
NoiseVar = Union[None, float, Literal["auto"]]

class Error(Exception):
    status: str
    code: int
    message: str
    n: Optional[int]
    rejected: Optional[int]

class ArgError(Error, ValueError): ...
class TooFewError(Error): ...
class NotPosDefError(Error): ...
class NoConvergenceError(Error): ...
class DegenerateError(Error): ...
class NonFiniteError(Error): ...
class RangeError(Error, ValueError): ...

class FitResult:
    center: Vec3
    radius: float
    n: int
    rejected: int
    eigenvalues: Vec3
    axis: Vec3
    trust_ratio: float
    leontief_ratio: float
    flags: list[str]
    flags_mask: int
    method: Literal["gdke", "ugdk", "geometric"]
    mode: Literal["sphere", "planar"]
    noise_var: Optional[float]
    noise_estimated: bool
    noise_capped: bool
    iterations: int
    rms: Optional[float]
    outliers: int
    center_cov: Optional[Mat3]
    radius_var: Optional[float]
    center_radius_cov: Optional[Vec3]
    def to_dict(self) -> dict[str, Any]: ...

class MultiResult:
    center: Vec3
    radii: npt.NDArray[np.float64]
    marker_n: npt.NDArray[np.int64]
    marker_rejected: npt.NDArray[np.int64]
    n: int
    markers: int
    skipped: int
    eigenvalues: Vec3
    axis: Vec3
    trust_ratio: float
    leontief_ratio: float
    flags: list[str]
    flags_mask: int
    method: Literal["gdke", "ugdk"]
    mode: Literal["sphere", "planar"]
    weight: Literal["equal", "samples"]
    rejected: int
    def to_dict(self) -> dict[str, Any]: ...

class NoiseEstimate:
    n: int
    noise_trace: float
    noise_var: float
    noise_var_std: float
    flags: list[str]
    rejected: int
    def to_dict(self) -> dict[str, Any]: ...

class Uncertainty:
    center_cov: Mat3
    radius_var: float
    center_radius_cov: Vec3
    noise_var: float
    def to_dict(self) -> dict[str, Any]: ...

class RefineResult:
    center: Vec3
    radius: float
    rms: float
    noise_var: float
    n: int
    iterations: int
    rejected: int
    def to_dict(self) -> dict[str, Any]: ...

class Estimate:
    center: Vec3
    radius: float
    n: int
    def to_dict(self) -> dict[str, Any]: ...

class Track:
    n: npt.NDArray[np.int64]
    centers: npt.NDArray[np.float64]
    radii: npt.NDArray[np.float64]
    def to_dict(self) -> dict[str, Any]: ...

def fit(points: ArrayLike, noise_var: NoiseVar = None, noise_cov: Optional[ArrayLike] = None,
        mode: Mode = "auto", refine: bool = False, *, planar_ratio: float = 0.0,
        gate: Optional[float] = None) -> FitResult: ...

def fit_multi(markers: Union[Sequence[ArrayLike], ArrayLike], noise_var: Optional[float] = None,
              noise_cov: Optional[ArrayLike] = None, mode: Mode = "auto",
              weight: Literal["equal", "samples"] = "equal", *,
              planar_ratio: float = 0.0) -> MultiResult: ...

class Moments:
    def __init__(self, points: Optional[ArrayLike] = None) -> None: ...
    @property
    def count(self) -> int: ...
    @property
    def rejected(self) -> int: ...
    def __len__(self) -> int: ...
    def add(self, points: ArrayLike) -> int: ...
    def merge(self, other: Moments) -> None: ...
    def reset(self) -> None: ...
    def copy(self) -> Moments: ...
    def stats(self) -> Tuple[Vec3, Mat3, Vec3]: ...
    def fit(self, noise_var: Optional[float] = None, noise_cov: Optional[ArrayLike] = None,
            mode: Mode = "auto", *, planar_ratio: float = 0.0) -> FitResult: ...
    def solve(self, noise_var: Optional[float] = None, noise_cov: Optional[ArrayLike] = None,
              mode: Mode = "auto", *, planar_ratio: float = 0.0) -> FitResult: ...
    def calibrate_noise(self, center: ArrayLike, radius: float) -> NoiseEstimate: ...
    def uncertainty(self, center: ArrayLike, radius: float, noise_var: float,
                    estimated: bool = False) -> Uncertainty: ...

class Incremental:
    def __init__(self, noise_var: Optional[float] = None,
                 noise_cov: Optional[ArrayLike] = None) -> None: ...
    @property
    def count(self) -> int: ...
    @property
    def rejected(self) -> int: ...
    def start(self, points: ArrayLike) -> Estimate: ...
    def add(self, points: ArrayLike) -> int: ...
    def update(self, x: ArrayLike) -> Estimate: ...
    def fit(self) -> Estimate: ...
    def estimate(self) -> Estimate: ...
    def track(self, points: ArrayLike) -> Track: ...
    def reset(self) -> None: ...

def calibrate_noise(points: ArrayLike, center: ArrayLike, radius: float) -> NoiseEstimate: ...
def calibration_std(noise_var: float, radius: float, n: int) -> float: ...
def coverage_eigs(kind: Kind, theta: float, radius: float) -> Tuple[float, float]: ...
def coverage_max_sigma(kind: Kind, theta: float, radius: float) -> float: ...
def coverage_min_theta(kind: Kind, sigma_over_r: float) -> float: ...
def coverage_estimate_theta(kind: Kind, eigenvalues: ArrayLike) -> float: ...
def residual_noise_var(points: ArrayLike, center: ArrayLike, radius: float) -> float: ...
def refine(points: ArrayLike, center: ArrayLike, max_iters: int = 0,
           tol: float = 0.0) -> RefineResult: ...
def uncertainty(points: ArrayLike, center: ArrayLike, radius: Optional[float] = None,
                noise_var: Optional[float] = None) -> Uncertainty: ...

# C3D files (the CLI's reader and writer, docs/c3d.md)
class C3D:
    labels: list[str]
    rate: float
    units: str
    points: npt.NDArray[np.float64]
    first_frame: int
    processor: str
    storage: str
    scale: float
    analog_channels: int
    analog_per_frame: int
    analog_rate: float
    zero_samples: int
    warnings: list[str]
    sources: dict[str, str]
    def to_dict(self) -> dict: ...

def read_c3d(path: Union[str, bytes, "os.PathLike[str]"]) -> C3D: ...
def write_c3d(src: Union[str, bytes, "os.PathLike[str]"], dst: Union[str, bytes, "os.PathLike[str]"],
              points: "Mapping[str, ArrayLike]", prefix: Optional[str] = None,
              descriptions: "Optional[Mapping[str, str]]" = None) -> bool: ...
def write_trc(src: Union[str, bytes, "os.PathLike[str]"], dst: Union[str, bytes, "os.PathLike[str]"],
              points: "Optional[Mapping[str, ArrayLike]]" = None, prefix: Optional[str] = None) -> None: ...

# Joint-centre API (sfit_cluster.h, sfit_joint.h)
CLUSTER_MAX_MARKERS: int
JOINT_MAX_CHILD: int

class Pose:
    rotation: Mat3
    translation: Vec3
    rms: float
    used: int
    def to_global(self, points: ArrayLike) -> npt.NDArray[np.float64]: ...
    def to_segment(self, points: ArrayLike) -> npt.NDArray[np.float64]: ...
    def to_dict(self) -> dict[str, Any]: ...

class Cluster:
    def __init__(self, template: ArrayLike) -> None: ...
    @classmethod
    def from_frames(cls, frames: ArrayLike) -> Cluster: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def count(self) -> int: ...
    @property
    def frames_used(self) -> int: ...
    def register(self, frame: ArrayLike) -> Pose: ...

class JointResult:
    center: Vec3
    axis: Vec3
    eigenvalues: Vec3
    radii: npt.NDArray[np.float64]
    marker_n: npt.NDArray[np.int64]
    n: int
    markers: int
    skipped: int
    trust_ratio: float
    leontief_ratio: float
    flags: list[str]
    flags_mask: int
    method: Literal["gdke", "ugdk", "default", "score", "sara"]
    mode: Literal["sphere", "planar"]
    frames: int
    rejected_frames: int
    residual_mean: float
    residual_max: float
    center_global: Optional[npt.NDArray[np.float64]]
    axis_global: Optional[npt.NDArray[np.float64]]
    valid: Optional[npt.NDArray[np.bool_]]
    cluster: Optional[Cluster]
    label_swaps: Optional[dict[str, Any]]
    center_cov: Optional[npt.NDArray[np.float64]]
    axis_cov: Optional[npt.NDArray[np.float64]]
    center_child: Optional[Vec3]
    axis_child: Optional[Vec3]
    marker_noise_var: Optional[float]
    marker_noise_var_parent: Optional[float]
    marker_noise_var_child: Optional[float]
    noise_source: Optional[Literal["registration_residuals", "given"]]
    untrusted: Optional[bool]
    reason: Optional[str]
    misfit: Optional[float]
    model_rms: Optional[float]
    child_cluster: Optional[Cluster]
    zero_missing: Optional[int]
    note: Optional[str]
    center_cov_model: Optional[Mat3]
    axis_cov_model: Optional[Mat3]
    skin_rms: Optional[float]
    skin_ratio: Optional[float]
    wobble_rms: Optional[float]
    info: Optional[list[str]]
    def to_dict(self) -> dict[str, Any]: ...

class Joint:
    def __init__(self, parent: Cluster, n_child: int, noise_var: Optional[float] = None,
                 noise_cov: Optional[ArrayLike] = None, mode: Mode = "auto",
                 weight: Literal["equal", "samples"] = "equal",
                 planar_ratio: float = 0.0, marker_noise_var: Optional[float] = None) -> None: ...
    @property
    def frames(self) -> int: ...
    @property
    def rejected_frames(self) -> int: ...
    def add(self, parent: ArrayLike, child: ArrayLike) -> int: ...
    def fit(self) -> JointResult: ...
    def solve(self) -> JointResult: ...
    def center_at(self, result: JointResult, parent: ArrayLike
                  ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.bool_]]: ...
    def noise_cov(self, marker_var: float) -> Mat3: ...
    def reset(self) -> None: ...

def joint_center(parent: ArrayLike, child: ArrayLike, template: Union[None, Cluster, ArrayLike] = None,
                 noise_var: Optional[float] = None, noise_cov: Optional[ArrayLike] = None,
                 mode: Mode = "auto", weight: Literal["equal", "samples"] = "equal",
                 marker_noise_var: Union[None, float, Literal["auto"]] = None,
                 method: Literal["mgdk", "default", "score", "sara"] = "default",
                 child_template: Union[None, Cluster, ArrayLike] = None,
                 repair_swaps: bool = True, zero_is_missing: bool = True) -> JointResult: ...

# A lab session (docs/session.md)
def session_model(model: Union[str, bytes, "os.PathLike[str]"]) -> dict[str, Any]: ...
def calibrate(model: Union[str, bytes, "os.PathLike[str]"],
              trials: Union[Sequence[Union[str, "os.PathLike[str]"]],
                            "Mapping[str, Union[str, os.PathLike[str], Mapping[str, ArrayLike]]]"],
              out: Optional[Union[str, "os.PathLike[str]"]] = None) -> dict[str, Any]: ...
def apply_session(session: Union[dict[str, Any], str, "os.PathLike[str]"],
                  trial: Union[str, "os.PathLike[str]", "Mapping[str, ArrayLike]"],
                  out: Optional[Union[str, "os.PathLike[str]"]] = None,
                  trc: Optional[Union[str, "os.PathLike[str]"]] = None) -> dict[str, Any]: ...

# The joint between two IMUs (docs/imu.md)
class ImuJointResult:
    joint: Literal["ball", "hinge"]
    r1: Vec3
    r2: Vec3
    r1_cov: Mat3
    r2_cov: Mat3
    axis1: Optional[Vec3]
    axis2: Optional[Vec3]
    axis1_cov: Optional[Mat3]
    axis2_cov: Optional[Mat3]
    acc_bias1: Vec3
    acc_bias2: Vec3
    resid_rms: float
    noise_rms: float
    hinge_ratio: float
    wobble_deg: float
    line_sd: float
    line_ratio: float
    line_off: float
    force_ratio: float
    rate_rms1: float
    rate_rms2: float
    n: int
    used: int
    flags: list[str]
    untrusted: bool
    reason: Optional[str]
    flags_mask: int
    def to_dict(self) -> dict[str, Any]: ...

def imu_joint(acc1: ArrayLike, gyr1: ArrayLike, acc2: ArrayLike, gyr2: ArrayLike,
              rate: float) -> ImuJointResult: ...
