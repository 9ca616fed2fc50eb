"""The cycle tables follow their schema: a key the schema does not know is refused when the
table is loaded, with the file, the cycle and the keys it accepts."""
from __future__ import annotations

import pytest

from ncverify.cycle_models import (CYCLE_KEYS, UNKNOWN_CYCLE, CycleModel, CycleTableError, ParameterSpec, check_cycle_model,
                                   load_cycle_table, read_cycle_table)
from ncverify.dialect import DIALECTS


@pytest.mark.parametrize("dialect", sorted(DIALECTS))
def test_every_cycle_table_follows_the_schema(dialect):
    models = load_cycle_table(dialect)
    assert models and all(isinstance(model, CycleModel) and model.name for model in models.values())
    assert all(isinstance(spec, ParameterSpec) for model in models.values() for spec in model.params.values())


def test_a_misspelt_key_names_the_file_the_cycle_and_the_accepted_keys():
    with pytest.raises(CycleTableError) as error:
        check_cycle_model("dialects/iso/cycles.toml", "iso.G81", {"name": "drilling", "retrackt": "rapid"})
    message = str(error.value)
    assert message.startswith("dialects/iso/cycles.toml: cycle iso.G81: unknown key retrackt; accepted keys: ")
    assert "retract" in message.split("accepted keys: ")[1].split(", ")


def test_a_misspelt_parameter_key_is_refused():
    model = {"name": "drilling", "params": {"Z": {"meaning": "bottom", "kind": "length", "requird": True}}}
    with pytest.raises(CycleTableError, match="parameter Z: unknown key requird"):
        check_cycle_model("dialects/iso/cycles.toml", "iso.G81", model)


def test_every_schema_key_is_used_by_some_table():
    used = {key for dialect in DIALECTS for model in read_cycle_table(dialect).values() for key in model}
    assert used == CYCLE_KEYS


def test_a_model_reads_its_facts_as_attributes_with_the_defaults_of_the_schema():
    drilling = load_cycle_table("iso")["iso.G81"]
    assert drilling.params["Z"].meaning and drilling.params["Z"].kind == "length"
    assert UNKNOWN_CYCLE.shape is None and UNKNOWN_CYCLE.params == {} and UNKNOWN_CYCLE.bottom == ()
