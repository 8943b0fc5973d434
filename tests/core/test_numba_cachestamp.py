"""The package-wide numba cache stamp (ringcore.cachestamp) on the N-body kernels."""
from ringcore.hydro import kernels as hydro_kernels


def test_every_nbody_kernel_is_stamped_with_all_kernel_sources():
    """The N-body step (integrator) calls kernels.py and gravity.py: the same package-wide stamp as hydro."""
    import os

    from ringcore import cachestamp
    from ringcore.nbody import gravity, integrator, kernels

    d = os.path.dirname(kernels.__file__)
    digest = cachestamp.sources_digest(d)
    assert digest != cachestamp.sources_digest(os.path.dirname(hydro_kernels.__file__))  # one stamp per package
    compiled = [getattr(m, n) for m in (integrator, kernels, gravity) for n in dir(m)
                if getattr(getattr(m, n), "_cache", None) is not None and getattr(m, n).__module__ == m.__name__]
    assert len(compiled) >= 5
    for fn in compiled:
        loc = fn._cache._impl._locator
        assert type(loc).__name__.startswith("Package") and loc.get_source_stamp()[1] == digest, fn
