"""From measured data to a gfrf model: polynomial NARX models identified by FROLS.

One module per step, each importing only those before it:

* :mod:`gfrf.identify.data` - :func:`~gfrf.identify.data.read_csv` (the columns of a
  CSV file) and the checks of data and fit settings, with their limits;
* :mod:`gfrf.identify.narx` - :func:`~gfrf.identify.narx.from_sysidentpy`, the exact
  converter of a fitted sysidentpy polynomial model, and
  :func:`~gfrf.identify.narx.narx_equation`;
* :mod:`gfrf.identify.frols` - FROLS as sysidentpy runs it (error reduction ratio
  ranking, :mod:`gfrf.identify.ols`, and an information criterion);
* :mod:`gfrf.identify.fit` - :func:`~gfrf.identify.fit.identify` (FROLS,
  held-out free-run error) and its :class:`~gfrf.identify.fit.Identification`;
* :mod:`gfrf.identify.validate`, :mod:`gfrf.identify.operating`,
  :mod:`gfrf.identify.noise`, :mod:`gfrf.identify.result` - hold-out validation
  (Billings-Voon correlation tests), operating points, NARMAX noise terms by extended
  least squares, and the :class:`~gfrf.identify.result.Identification`;
* :mod:`gfrf.identify.floor`, :mod:`gfrf.identify.prune`, :mod:`gfrf.identify.spread`,
  :mod:`gfrf.identify.trust` - the noise floor the held-out free run is judged against,
  backward elimination of terms on the held-out free run, r* with its spread over the
  coefficients' uncertainty, and :func:`~gfrf.identify.trust.identified_verdict` (stable
  only below the spread's lower end);
* :mod:`gfrf.identify.output` - :func:`~gfrf.identify.output.model_file_text`,
  :func:`~gfrf.identify.output.load_text` and :func:`~gfrf.identify.output.write_atomic`:
  from the identification to a model file that ``gfrf verdict`` and ``gfrf report``
  read like any other.

Identification does not import sysidentpy (its FROLS is reproduced, and checked against
it in the tests); :func:`~gfrf.identify.narx.from_sysidentpy` converts a model a user
fitted with it.  The public names of these modules are re-exported
here.  Also: :mod:`gfrf.identify.example` (the worked example's data generator),
:mod:`gfrf.report.identified` (its report page), :mod:`gfrf.bench.identify`
(identification timings).
"""

from __future__ import annotations

from gfrf.identify.data import (
    MAX_CANDIDATES,
    MAX_SAMPLES,
    MIN_SAMPLES,
    candidate_count,
    read_csv,
    read_data,
)
from gfrf.identify.fit import (
    SAME_TERMS_RTOL,
    Identification,
    free_run,
    identify,
    same_terms,
)
from gfrf.identify.narx import from_sysidentpy, narx_equation
from gfrf.identify.output import load_text, model_file_text, write_atomic
from gfrf.identify.trust import identified_verdict

__all__ = ["Identification", "from_sysidentpy", "identify", "read_csv", "free_run",
           "model_file_text", "load_text", "narx_equation", "write_atomic", "candidate_count",
           "same_terms", "SAME_TERMS_RTOL", "read_data",
           "identified_verdict", "MAX_CANDIDATES", "MAX_SAMPLES",
           "MIN_SAMPLES"]
