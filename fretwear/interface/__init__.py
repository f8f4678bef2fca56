"""Contact interfaces with many node pairs: the paper's stated aim (section 1.2), wear at every contact node.

Layers, bottom up:

* the model is :class:`fretwear.model.Model` with its ``pairs``
  (:class:`~fretwear.model.ContactPairs`: node pairs, normals, tributary areas,
  gaps), reduced by :func:`fretwear.model.craig_bampton`;
* :mod:`~fretwear.interface.mesh`, :mod:`~fretwear.interface.fe`: the
  cylinder-on-flat fretting benchmark in plane strain, meshed and assembled
  with scikit-fem (:func:`cylinder_on_flat`);
* :mod:`~fretwear.interface.sphere_mesh`, :mod:`~fretwear.interface.sphere`: the
  3-D sphere-on-flat benchmark (half model, hexahedra; :func:`sphere_on_flat`),
  its exact static condensation on the contact (:func:`sphere_static_model`)
  and its Hertz, Mindlin and Mindlin-Deresiewicz anchors
  (:func:`sphere_static_benchmark`, :func:`sphere_cyclic_dissipation`);
* :mod:`~fretwear.interface.paper`: the paper's 2-DOF example as a one-pair
  interface (:func:`paper_interface`);
* :mod:`~fretwear.interface.modelfile`: matrices exported from another FE code
  (Matrix Market or ``.npz``) plus the contact pairs, in a TOML file
  (:func:`read_interface_model`);
* :mod:`~fretwear.interface.reduction`: the condensation on the contact
  coordinates (:class:`ContactCondensation`, eq. 11);
* :mod:`~fretwear.interface.static`: quasi-static contact (Hertz,
  Cattaneo-Mindlin; :func:`static_benchmark`);
* :mod:`~fretwear.interface.contact`, :mod:`~fretwear.interface.kernels`: the
  coupled normal/tangential DLFT law of eq. 17-23 per pair (Numba, in
  :mod:`fretwear.hbm.coupled`) and the compiled Newton loop and load walk (the
  shared ones of :mod:`fretwear.hbm.newton`, handed this law);
* :mod:`~fretwear.interface.periodic`: the periodic response
  (:class:`InterfaceProblem`, :func:`solve_interface`);
* :mod:`~fretwear.interface.history`: the record of a nodal wear history
  (:class:`InterfaceWearHistory`);
* :mod:`~fretwear.interface.wear`: nodal Archard wear with pressure
  redistribution (:func:`wear_interface`), warm-started sweeps
  (:func:`sweep_interface`) and FRFs before/after wear (:func:`frf`);
* :mod:`~fretwear.interface.jobs`: the front functions' interface side
  (``fretwear.solve_periodic``, ``fretwear.sweep``, ``fretwear.wear_history``,
  ``fretwear.static_contact`` on a model with pairs);
* :mod:`~fretwear.interface.polynomial`: the polynomial slow-time method
  (eq. 25-29, :func:`wear_polynomial_interface`, ``wear_interface(method="polynomial")``);
* :mod:`~fretwear.interface.time_integration`: direct time integration with the
  same contact law (backward Euler, :func:`integrate_interface`), the check;
* the ``fretwear interface`` command is :mod:`fretwear.cli.interface`.
"""

from importlib import import_module

#: public names and their modules, imported on first use (``fretwear interface --help`` stays light)
_EXPORTS = {
    "ContactCondensation": "reduction",
    "CylinderOnFlat": "fe",
    "InterfaceProblem": "periodic",
    "InterfaceSolution": "periodic",
    "InterfaceWearHistory": "history",
    "cylinder_on_flat": "fe",
    "frf": "wear",
    "read_interface_model": "modelfile",
    "paper_interface": "paper",
    "solve_interface": "periodic",
    "solve_static": "static",
    "SphereOnFlat": "sphere",
    "sphere_cyclic_dissipation": "sphere",
    "sphere_on_flat": "sphere",
    "sphere_static_benchmark": "sphere",
    "sphere_static_model": "sphere",
    "sweep_interface": "wear",
    "static_benchmark": "static",
    "wear_interface": "wear",
    "wear_polynomial_interface": "polynomial",
    "integrate_interface": "time_integration",
    "write_interface_model": "modelfile",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(list(globals()) + __all__)
