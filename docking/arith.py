"""Arithmetic whose bits do not depend on which x86-64 CPU runs it.

numpy and OpenBLAS pick kernels by the CPU they find, and some of those kernels round
differently: numpy's own float64 ``exp``, ``log``, ``tan`` and ``arctan`` under AVX-512 (the C
library's elsewhere), and OpenBLAS's dot, matrix-vector and matrix products, whose kernel is
chosen per CPU family (``OPENBLAS_CORETYPE``: Haswell, SkylakeX, Zen, ...) and sums in
another order. Every product and exponential a run computes goes through this module
instead:

* :func:`exp`: the C library's ``exp`` (``math.exp``), element by element. It is what numpy
  calls on machines without AVX-512, so it gives the same bits as ``np.exp`` there;
* products: ``np.einsum`` without ``optimize``, numpy's own loop, compiled for the baseline
  instruction set of the wheel (the same on every x86-64 CPU) and never handed to BLAS.

tests/test_platform.py computes a short run in subprocesses under every numpy dispatch level,
OpenBLAS core type and OpenCV setting the machine can run, and compares its digest with the
recording. The C library's own ``exp``, ``sin`` and ``cos`` (which MuJoCo calls too) take
other code paths on CPUs without FMA and AVX2 (x86-64-v3), so runs are the same on x86-64-v3
machines and newer, with the same libraries (the lock file).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["dot", "exp", "matmul", "matvec", "rowdot"]


def exp(x: np.ndarray) -> np.ndarray:
    """``exp`` of a float64 array, element by element through the C library (``math.exp``)."""
    return np.array([math.exp(v) for v in x.tolist()], dtype=np.float64).reshape(np.shape(x))


def dot(x: np.ndarray, y: np.ndarray) -> float:
    """``x @ y`` of two vectors, as a float."""
    return float(np.einsum("i,i->", x, y))


def matvec(A: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``A @ x`` of a matrix and a vector."""
    return np.einsum("ij,j->i", A, x)


def rowdot(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """The dot product of each row of ``A`` with the same row of ``B``."""
    return np.einsum("ij,ij->i", A, B)


def matmul(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``A @ B`` of two matrices."""
    return np.einsum("ij,jk->ik", A, B)
