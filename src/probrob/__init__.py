"""probrob: the library behind the *probrob* book.

Tested implementations of *Probabilistic Robotics* (Thrun, Burgard & Fox, 2005),
chapters 5-7. Function names are the book's algorithm names; each docstring cites
the table it implements and the deck formula it corrects, if any.

The module map (each module holds one kind of thing; its docstring says what it does not):

* :mod:`probrob.distributions` — the densities and samplers of Table 5.2 (and 5.4);
* :mod:`probrob.motion` — the motion models, Tables 5.1, 5.3, 5.5, 5.6, and :math:`g, G, V`;
* :mod:`probrob.kinematics` — wheel odometry and dead reckoning (the Turkish and CIR decks);
* :mod:`probrob.sensors` — the measurement models, Tables 6.1–6.5, and :math:`h, H`;
* :mod:`probrob.maps` — occupancy grids, their distance field and ray casting;
* :mod:`probrob.localization` — the Gaussian filters, Tables 7.2–7.4, and ``run_filter``;
* :mod:`probrob.mcl` — Monte Carlo localization, Tables 8.2–8.4, and the sampler of Table 4.4;
* :mod:`probrob.grid_localization` — grid localization, Table 8.1 (a histogram filter over poses);
* :mod:`probrob.evaluation` — the NEES, χ² quantiles and covariance ellipses of estimates;
* :mod:`probrob.fitting` — noise parameters fitted to recorded data (ML and moment fits);
* :mod:`probrob.simulation` — simulated landmark worlds and runs;
* :mod:`probrob.datasets` — the loaders of the real recordings;
* :mod:`probrob.angles` — angle wrapping, differences and circular means;
* :mod:`probrob.plotting`, :mod:`probrob.widgets` — figures, sliders and players;
* :mod:`probrob.live` — the live widgets that recompute a table in the browser: one module
  per family (motion, sensors, kinematics, localization, mcl), a core, one JavaScript kernel
  per table on one runtime (re-exported by :mod:`probrob.widgets`);
* :mod:`probrob.prose` — numbers for the prose; :mod:`probrob.exercises` — exercise checks;
* ``probrob._validation`` — the one layer of argument checks.
"""

__version__ = "0.1.0"
