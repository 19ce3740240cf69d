"""The host's vector extensions, and the width Mitsuba's LLVM backend compiles for.

Every speed figure names the host it was measured on: Mitsuba's `llvm_*` variants
compile for the host's full width (16 lanes of float32 on AVX-512, 8 on AVX2), while
lavapipe's width is its own (Mesa 22.3: 8 lanes). `vector_extensions()` reads
/proc/cpuinfo; `restrict_llvm("avx2")`, called before `mi.set_variant`, makes Dr.Jit
compile for an AVX2 host (Haswell, 8 lanes) on any x86-64 CPU, so that one machine
measures both kinds of host.

Dr.Jit exposes the target only in C++ (drjit-core's `jit_llvm_set_target`,
`jit_llvm_vector_width`, `jit_llvm_target_cpu`), so they are called through ctypes by
their mangled names; `llvm_info()` says what the backend compiles for.
"""

import ctypes
import os
import platform

# Extensions that decide a float32 lane count, widest first.
WIDTHS = (("avx512f", "AVX-512", 16), ("avx2", "AVX2", 8), ("avx", "AVX", 8), ("sse4_2", "SSE4.2", 4))

# --llvm-target choices: (target CPU, features, vector width); None = the host's own.
TARGETS = {
    "native": None,
    "avx2": (b"haswell",
             b"+avx2,+fma,+f16c,+bmi,+bmi2,+lzcnt,+popcnt,"
             b"-avx512f,-avx512vl,-avx512dq,-avx512bw,-avx512cd,-avx512vbmi,-avx512ifma",
             8),
}

_SYMBOLS = {
    "set_target": "_Z19jit_llvm_set_targetPKcS0_j",
    "vector_width": "_Z21jit_llvm_vector_widthv",
    "target_cpu": "_Z19jit_llvm_target_cpuv",
}


def vector_extensions():
    """{'name': 'AVX-512', 'lanes': 16, 'flags': [...], 'cpu': model name} of this host."""
    flags, model = set(), platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                key, _, value = line.partition(":")
                key = key.strip()
                if key == "flags" and not flags:
                    flags = set(value.split())
                elif key == "model name":
                    model = value.strip()
    except OSError:
        pass
    for flag, name, lanes in WIDTHS:
        if flag in flags:
            break
    else:
        name, lanes = "none of AVX/SSE4.2", 1
    vector = sorted(f for f in flags if f.startswith(("avx", "fma", "sse4")))
    return {"name": name, "lanes": lanes, "flags": vector, "cpu": model}


def describe_host():
    """One line for a benchmark's header, e.g. 'AMD EPYC, AVX-512 (16 float32 lanes)'."""
    h = vector_extensions()
    return "%s, %s (%d float32 lanes)" % (h["cpu"], h["name"], h["lanes"])


def _core():
    import drjit

    return ctypes.CDLL(os.path.join(os.path.dirname(drjit.__file__), "libdrjit-core.so"))


def _function(lib, name, restype, argtypes=()):
    try:
        f = getattr(lib, _SYMBOLS[name])
    except AttributeError:
        raise SystemExit("this Dr.Jit has no %s (%s): cannot restrict its LLVM target"
                         % (name, _SYMBOLS[name]))
    f.restype, f.argtypes = restype, list(argtypes)
    return f


def restrict_llvm(target):
    """Makes Dr.Jit's LLVM backend compile for `target` (a TARGETS key). Call it before
    `mi.set_variant`; 'native' leaves the host's own target."""
    if target not in TARGETS:
        raise SystemExit("unknown LLVM target '%s' (known: %s)" % (target, ", ".join(TARGETS)))
    if TARGETS[target] is None:
        return
    cpu, features, width = TARGETS[target]
    f = _function(_core(), "set_target", None, (ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32))
    f(cpu, features, width)


def llvm_info():
    """{'cpu': target CPU, 'lanes': vector width} the LLVM backend compiles for (after
    an llvm variant is set and has run)."""
    lib = _core()
    width = _function(lib, "vector_width", ctypes.c_uint32)()
    cpu = _function(lib, "target_cpu", ctypes.c_char_p)()
    return {"cpu": (cpu or b"").decode(), "lanes": int(width)}


if __name__ == "__main__":
    print(describe_host())
