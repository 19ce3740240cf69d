//! The wavefront renderer: queues, per-bounce dispatch, integrators, film.
