"""Contact interfaces with many node pairs: the paper's stated aim (section 1.2), wear at every contact node.

Layers, bottom up:

* the model is :class:`fretwear.model.Model` with its ``pairs``
  (:class:`~fretwear.model.ContactPairs`: node pairs, normals, tributary areas,
  gaps), reduced by :func:`fretwear.model.craig_bampton`;
* ``fretwear.interface.mesh``, ``fretwear.interface.fe``: the
  cylinder-on-flat fretting benchmark in plane strain, meshed and assembled
  with scikit-fem (:func:`cylinder_on_flat`);
* ``fretwear.interface.sphere_mesh``, ``fretwear.interface.sphere``: the
  3-D sphere-on-flat benchmark (half model, hexahedra; :func:`sphere_on_flat`),
  its exact static condensation on the contact (:func:`sphere_static_model`)
  and its Hertz, Mindlin and Mindlin-Deresiewicz anchors
  (:func:`sphere_static_benchmark`, :func:`sphere_cyclic_dissipation`);
* ``fretwear.interface.paper``: the paper's 2-DOF example as a one-pair
  interface (:func:`paper_interface`);
* ``fretwear.interface.modelfile``: matrices exported from another FE code
  (Matrix Market or ``.npz``) plus the contact pairs, in a TOML file
  (:func:`read_interface_model`);
* ``fretwear.interface.reduction``: the condensation on the contact
  coordinates (:class:`ContactCondensation`, eq. 11);
* ``fretwear.interface.static``: quasi-static contact (Hertz,
  Cattaneo-Mindlin; :func:`static_benchmark`);
* ``fretwear.interface.contact``, ``fretwear.interface.kernels``: the
  coupled normal/tangential DLFT law of eq. 17-23 per pair (Numba, in
  ``fretwear.hbm.coupled``) and the compiled Newton loop and load walk (the
  shared ones of ``fretwear.hbm.newton``, handed this law);
* ``fretwear.interface.periodic``: the periodic response
  (:class:`InterfaceProblem`, :func:`solve_interface`);
* ``fretwear.interface.history``: the record of a nodal wear history
  (:class:`InterfaceWearHistory`);
* ``fretwear.interface.wear``: nodal Archard wear with pressure
  redistribution (:func:`wear_interface`), warm-started sweeps
  (:func:`sweep_interface`) and FRFs before/after wear (:func:`frf`);
* ``fretwear.interface.jobs``: the front functions' interface side
  (``fretwear.solve_periodic``, ``fretwear.sweep``, ``fretwear.wear_history``,
  ``fretwear.static_contact`` on a model with pairs);
* ``fretwear.interface.polynomial``: the polynomial slow-time method
  (eq. 25-29, :func:`wear_polynomial_interface`, ``wear_interface(method="polynomial")``);
* ``fretwear.interface.time_integration``: direct time integration with the
  same contact law (backward Euler, :func:`integrate_interface`), the check;
* the ``fretwear interface`` command is ``fretwear.cli.interface``.
"""

from importlib import import_module

#: public names and their modules, imported on first use (``fretwear interface --help`` stays light)
_EXPORTS = {
    "ContactCondensation": "reduction",
    "CylinderOnFlat": "fe",
    "InterfaceProblem": "periodic",
    "InterfaceSolution": "periodic",
    "InterfaceWearHistory": "history",
    "cycle_state": "history",
    "fretting_loop": "history",
    "shear_traction": "history",
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
