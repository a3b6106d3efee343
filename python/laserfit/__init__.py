"""laserfit: um-precise registration of laser line scans against CAD references (millimetres).

    import laserfit
    r = laserfit.register(scan_xyz, ref_xyz, ref_normals=ref_n, prior=T_arm)  # N x 3 arrays
    r.status, r.T_scan_ref, r.inlier_rmse_mm, r.covariance

Clouds are N x 3 (or H x W x 3 for an organized scan, NaN = no measurement) float32 or float64
arrays, or paths of PCD / PLY files; poses are 4 x 4 arrays. Bad input raises laserfit.Error with
one line naming the file and the problem.
"""
from ._laserfit import (Error, RegistrationResult, __version__, import_mesh, read_cloud,
                        refcloud, register, scan, write_cloud)

__all__ = ["Error", "RegistrationResult", "__version__", "import_mesh", "read_cloud", "refcloud",
           "register", "scan", "write_cloud"]
