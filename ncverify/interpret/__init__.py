"""Stage 3, interpret: the abstract machine (:mod:`.interpreter`), its control flow
(:mod:`.control_flow`), canned-cycle expansion and the shared hole model (:mod:`.cycles`)
and the dialects' run-time code (:mod:`.heidenhain`, :mod:`.sinumerik_cycles`,
:mod:`.fagor_cycles`, :mod:`.fagor`, :mod:`.modal_call`)."""
from . import cycles, fagor_cycles, sinumerik_cycles
from .interpreter import Interpreter, MachineState

cycles.install(sinumerik_cycles.CYCLES, fagor_cycles.CYCLES)

__all__ = ["Interpreter", "MachineState"]
