"""The numba kernels: bitwise equal to the numpy references, imported lazily by
:mod:`pmplan.backends` (importing a kernel module imports numba).

* :mod:`~pmplan.kernels.common` -- what they share: the numba import, the flag bits, the
  thresholds of the filter and the certificate, TwoSum / TwoProduct, the distance of a piece;
* :mod:`~pmplan.kernels.obstacle_line` -- the obstacle-line planner and its certificate (the
  scalar kernel and the SIMD lanes);
* :mod:`~pmplan.kernels.planar` -- the planar three-obstacle planner and its certificate;
* :mod:`~pmplan.kernels.validation` -- finite coordinates, distinct points;
* :mod:`~pmplan.kernels.box` -- the maps of a workspace box (:mod:`pmplan.workspace`).

A new planner's kernel is one module here, called by its glue in :mod:`pmplan.backends.numba`.
"""
