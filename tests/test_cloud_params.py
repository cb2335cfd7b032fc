"""Each cloud parameter is written once, as a CloudParams field with its range and help text; PARAMS (what the
console, the panel and the scene file read) is those fields, so the two cannot disagree."""
from dataclasses import FrozenInstanceError, fields, replace

import pytest

from app.model.clouds.scene import PARAM, PARAMS, CloudParams, ParamError
from app.views.clouds_panel import GROUPS, TOGGLES


def test_params_are_the_fields_of_cloud_params_in_order_with_their_defaults():
    defaults = CloudParams()
    assert [p.name for p in PARAMS] == [f.name for f in fields(CloudParams)] and len(PARAMS) == 39
    assert {p.name: p.default for p in PARAMS} == defaults.values()
    assert list(PARAM) == [p.name for p in PARAMS]
    for p in PARAMS:
        assert type(p.default) is (int if p.integer else float), p.name
        assert p.lo <= p.default <= p.hi and p.text, p.name
        assert not p.choices or (p.integer and p.default in p.choices), p.name
        assert defaults.with_value(p.name, p.default) == defaults  # each default passes its own check


def test_whole_number_parameters_are_the_int_fields():
    assert [p.name for p in PARAMS if p.integer] == ["shape_noise", "detail_noise", "curl_noise", "light_samples",
                                                     "multiscatter", "phase_max", "ground_shadows", "physical_sky"]
    assert PARAM["light_samples"].choices == (6, 30)
    with pytest.raises(ParamError, match="light_samples must be one of 6, 30, got 7"):
        CloudParams().with_value("light_samples", 7)
    with pytest.raises(ParamError, match="coverage must be within 0..2, got 3"):
        CloudParams().with_value("coverage", 3)


def test_cloud_params_stay_a_frozen_value_with_keyword_fields():
    params = CloudParams(coverage=1.6, light_samples=30)
    assert (params.coverage, params.light_samples, params.density) == (1.6, 30, PARAM["density"].default)
    assert replace(params, density=2.0).density == 2.0 and params.density == PARAM["density"].default
    with pytest.raises(FrozenInstanceError):
        params.coverage = 0.5


def test_the_panel_shows_every_parameter_once():
    own_rows = ["weather_blend", "light_samples", "phase_max"]
    shown = [name for _title, names in GROUPS for name in names] + list(TOGGLES) + own_rows
    assert sorted(shown) == sorted(PARAM)
