"""From measurements to model parameters (section 5.4 and Table 4.6).

:mod:`.coupling` turns the TIR pipeline's tables into model inputs (measured contact, lever
arm, Eq. 5.21); :mod:`.identify` identifies the element parameters of the tread-block models
from deflection series and a steady characteristic; :mod:`.table_4_6` calibrates the dry/wet
model to the thesis's Table 4.6; :mod:`.workflow` is the whole calibration from measured
results (:func:`calibrate_from_results`).
"""

from friction_model.identification.coupling import *  # noqa: F403
from friction_model.identification.coupling import __all__ as _coupling
from friction_model.identification.identify import *  # noqa: F403
from friction_model.identification.identify import __all__ as _identify
from friction_model.identification.table_4_6 import *  # noqa: F403
from friction_model.identification.table_4_6 import __all__ as _table_4_6
from friction_model.identification.workflow import *  # noqa: F403
from friction_model.identification.workflow import __all__ as _workflow

__all__ = [*_coupling, *_identify, *_table_4_6, *_workflow]
