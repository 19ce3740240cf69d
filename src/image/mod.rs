//! Image I/O, tonemapping and error metrics.
