//! Acceleration structures: the BVH built on the host and flattened for the kernels.
