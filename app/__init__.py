"""The fretwear dashboard (``panel serve app/app.py``).

* :mod:`app.backend`: the library calls, their shared cache and the worker threads;
* :mod:`app.state`: the controls, the settings they define and the computations (tasks);
* :mod:`app.scenes`: one module per tab: what it computes, draws and exports;
* :mod:`app.session`: the task runner of every tab, and one browser session: which scene is
  visible, the selected point, the runs in the background and their progress;
* :mod:`app.app`: the Panel page;
* :mod:`app.warmup`: the warm-up hook (``panel serve app/app.py --setup app/warmup.py``).

No physics lives here: every number shown comes from a :mod:`fretwear` call.
"""
