"""What the influence operator builds and keeps, and the FFTW wisdom kept between runs.

Tolerances: none where results must be bit-identical (estimate plans with or without a
wisdom file; products through buffers shared by several batch sizes). The quadrant-built
kernels are compared with the element integrals corner by corner (``element_integrals``,
four corner functions per element): they differ by the rounding of the corner coordinates
((i ± ½)Δx as one product instead of iΔx ± ½Δx) amplified by the cancellation of the four
corners, ~1e-13 of the largest coefficient at 64² (measured 1.2e-13), hence 1e-12.
"""

from __future__ import annotations

import numpy as np
import pytest

from engine.grid import Grid
from engine.kernels import influence, wisdom
from engine.kernels.fft import RealFFTPair, wrap_kernel
from engine.kernels.influence import (
    KERNEL_INTEGRALS,
    KERNEL_PARITY,
    SurfaceInfluence,
    _combine,
    element_integrals,
    kernel_quadrant,
    kernel_quadrants,
)
from engine.kernels.operator import HalfSpaceOperator
from engine.material import MaterialPair, paper_material


def test_quadrant_kernels_match_element_integrals_and_are_exactly_even_or_odd():
    grid, material = Grid(9, 6, 1.0, 0.7), paper_material()
    operator = HalfSpaceOperator(grid, material)
    index_x, index_y = np.arange(-8, 9), np.arange(-5, 6)
    ox, oy = np.meshgrid(grid.dx * index_x, grid.dy * index_y, indexing="ij")
    for key, integrals in KERNEL_INTEGRALS.items():
        direct = _combine(key, element_integrals(ox, oy, grid.dx, grid.dy, integrals), material)
        values = operator.kernel(key, index_x, index_y)
        scale = np.abs(direct).max()
        np.testing.assert_allclose(values, direct, rtol=0, atol=1e-12 * scale, err_msg=key)
        parity_x, parity_y = KERNEL_PARITY[key]
        assert np.array_equal(values[::-1], parity_x * values), key
        assert np.array_equal(values[:, ::-1], parity_y * values), key


def test_quadrants_do_not_depend_on_the_blocks_or_the_kernels_evaluated_together(monkeypatch):
    """Each corner value is computed element by element (bit for bit, whatever the blocks)."""
    grid, material = Grid(23, 17, 1.0, 0.7), paper_material()
    keys = tuple(KERNEL_INTEGRALS)
    alone = {key: kernel_quadrant(grid, material, key, grid.shape) for key in keys}
    monkeypatch.setattr(influence, "BLOCK_ELEMENTS", 40)  # blocks of 2 rows of corners
    monkeypatch.setattr(influence, "BLOCK_ROWS", 2)
    together = kernel_quadrants(grid, material, keys, grid.shape)
    for key in keys:
        assert np.array_equal(together[key], alone[key]), key


def test_spectra_from_the_mirrored_half_are_the_2d_transforms_of_the_kernels():
    """The operator transforms the first n_x rows of each circulant kernel and mirrors the row
    spectra (``PaddedTransforms.forward_mirrored``): the 2-D real FFT of the whole wrapped
    kernel (numpy's), to 1e-14 of the largest value (rounding of two FFT implementations)."""
    grid, material = Grid(12, 9, 1.0, 0.8), paper_material()
    operator = HalfSpaceOperator(grid, material)
    influence_kernels = SurfaceInfluence.build(grid, material).kernels
    for key, kernel in influence_kernels.items():
        wrapped = wrap_kernel(kernel, operator.padded_shape)
        expected = np.fft.rfft2(wrapped) / wrapped.size
        got = operator.spectrum(key)
        scale = np.abs(expected).max()
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14 * scale, err_msg=key)


def test_outputs_into_work_arrays_are_the_same_bits():
    grid = Grid(14, 11, 1.0, 0.8)
    operator = HalfSpaceOperator(grid, paper_material())
    pressure = np.random.default_rng(5).random(grid.shape)
    out = np.empty(grid.shape)
    assert operator.apply_normal(pressure, out=out) is out
    assert np.array_equal(out, operator.apply_normal(pressure))
    assert operator.preconditioner.normal(pressure, out=out) is out
    assert np.array_equal(out, operator.preconditioner.normal(pressure))


def test_frictionless_case_builds_only_the_spectra_it_needs():
    grid = Grid.square(16, 1.0)
    uncoupled = MaterialPair(200e3, 0.3, 200e3, 0.3)
    assert uncoupled.coupling == 0.0
    operator = HalfSpaceOperator(grid, uncoupled)
    operator.apply_normal(np.ones(grid.shape))
    ux, uy = operator.coupling_to_tangential(np.ones(grid.shape))
    assert set(operator._spectra) == {"zz"}  # no coupling and no tangential spectra
    assert not ux.any() and not uy.any()
    coupled = HalfSpaceOperator(grid, paper_material())
    coupled.apply_normal(np.ones(grid.shape))
    assert set(coupled._spectra) == {"zz"}
    coupled.coupling_to_tangential(np.ones(grid.shape))  # the slip of a frictionless case
    assert set(coupled._spectra) == {"zz", "zx", "zy"}
    # 2n_x (n_y + 1) values each: real for A_zz (even), k of ik for A_zx, A_zy (odd).
    assert coupled.spectra_bytes == 3 * 32 * 17 * 8
    # a frictional solve keeps them whole, 0 + ik (one complex product each), bit for bit
    slip = coupled.coupling_to_tangential(np.arange(256.0).reshape(grid.shape))
    coupled.apply(*np.ones((3, *grid.shape)))
    assert coupled.spectra_bytes == (1 + 2 * 2 + 3) * 32 * 17 * 8
    again = coupled.coupling_to_tangential(np.arange(256.0).reshape(grid.shape))
    assert all(np.array_equal(a, b) for a, b in zip(slip, again, strict=True))


def test_uncoupled_products_leave_out_the_zero_coupling_blocks():
    """K = 0: A_zx and A_zy are zero (proportional to K), so a frictional case neither builds
    nor applies them; the full block gives the bits of its blocks taken apart (A_tt q, A_zz p),
    and ``apply_normal_later`` makes u_n only when asked, within one counted application."""
    grid = Grid(12, 10, 1.0, 0.8)
    uncoupled = MaterialPair(200e3, 0.3, 200e3, 0.3)
    fields = np.random.default_rng(5).standard_normal((3, *grid.shape))
    operator = HalfSpaceOperator(grid, uncoupled)
    u = np.array(operator.apply(*fields))
    operator.symbol_bound()
    assert set(operator._spectra) == {"zz", "xx", "xy", "yy"}
    assert np.array_equal(u[:2], np.array(operator.apply_tangential(fields[0], fields[1])))
    assert np.array_equal(u[2], operator.apply_normal(fields[2]))
    count = operator.applications
    assert not operator.coupling_to_normal(fields[0], fields[1]).any()
    ux, uy, normal = operator.apply_normal_later(*fields)
    assert operator.applications == count + 2
    assert np.array_equal(np.array([ux, uy]), u[:2])
    assert np.array_equal(normal(), u[2])
    assert operator.applications == count + 2  # u_n is part of the same application
    zero = np.zeros(grid.shape)
    ux, uy, normal = operator.apply_normal_later(zero, zero, fields[2])
    assert not ux.any() and not uy.any()
    assert np.array_equal(normal(), u[2])


def test_products_do_not_depend_on_the_batch_sizes_asked_before():
    """The FFT buffers grow with the largest block asked; the results stay the same bits."""
    grid = Grid(12, 10, 1.0, 0.8)
    fields = np.random.default_rng(3).standard_normal((3, *grid.shape))
    fresh = HalfSpaceOperator(grid, paper_material())
    normal_first = fresh.apply_normal(fields[2])
    full_first = np.array(fresh.apply(*fields))
    grown = HalfSpaceOperator(grid, paper_material())
    full = np.array(grown.apply(*fields))
    assert np.array_equal(full, full_first)
    assert np.array_equal(grown.apply_normal(fields[2]), normal_first)


def test_released_buffers_are_made_again_with_the_same_bits():
    """A static case lets go of the padded transforms before its stress plane; the next
    products (a later case on the same operator) make them again with the same plans."""
    grid = Grid(12, 10, 1.0, 0.8)
    fields = np.random.default_rng(4).standard_normal((3, *grid.shape))
    operator = HalfSpaceOperator(grid, paper_material())
    normal, full = operator.apply_normal(fields[2]), np.array(operator.apply(*fields))
    operator.release_buffers()
    assert operator._transforms is None and operator._targets is None
    assert set(operator._spectra) >= {"zz", "zx", "zy"}  # the spectra stay
    assert np.array_equal(operator.apply_normal(fields[2]), normal)
    operator.release_buffers()
    assert np.array_equal(np.array(operator.apply(*fields)), full)


def test_estimate_plans_give_the_same_bits_with_or_without_wisdom(tmp_path, monkeypatch):
    monkeypatch.setenv("ENGINE_FFTW_WISDOM", str(tmp_path / "wisdom.pickle"))
    data = np.random.default_rng(4).standard_normal((2, 60, 60))
    wisdom.clear()
    without = _spectrum((2, 60, 60), data, "FFTW_ESTIMATE")
    _spectrum((2, 60, 60), data, "FFTW_MEASURE")  # a timed plan: wisdom written
    assert wisdom.wisdom_path().exists()
    wisdom.load()
    assert np.array_equal(_spectrum((2, 60, 60), data, "FFTW_ESTIMATE"), without)
    assert wisdom.clear() == tmp_path / "wisdom.pickle"
    assert not (tmp_path / "wisdom.pickle").exists()


def test_wisdom_location_and_switch(tmp_path, monkeypatch):
    monkeypatch.delenv("ENGINE_FFTW_WISDOM", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    path = wisdom.wisdom_path()
    assert path.parent == tmp_path / "fretting-engine" and path.name.startswith("fftw-wisdom-")
    monkeypatch.setenv("ENGINE_FFTW_WISDOM", "off")
    assert wisdom.wisdom_path() is None
    wisdom.save()  # nothing kept, no error
    (tmp_path / "damaged").write_bytes(b"not wisdom")
    monkeypatch.setenv("ENGINE_FFTW_WISDOM", str(tmp_path / "damaged"))
    wisdom.load()  # a damaged file is ignored


def _spectrum(shape, data, effort) -> np.ndarray:
    pair = RealFFTPair(shape, effort=effort)
    pair.real[...] = data
    return pair.forward().copy()


@pytest.fixture(autouse=True)
def _no_user_wisdom(tmp_path, monkeypatch):
    """Tests never write the user's cache."""
    monkeypatch.setenv("ENGINE_FFTW_WISDOM", str(tmp_path / "test-wisdom.pickle"))
