import io
import json

import pandas as pd

import rocklab


def test_records_equal_the_cli_json(cli):
    ours = rocklab.records()
    theirs = pd.DataFrame(json.loads(cli("records", "--json")))
    pd.testing.assert_frame_equal(ours, theirs)
    # PGA in g from the data: positive and below 3 g for every real record.
    assert ((ours["pga_g"] > 0) & (ours["pga_g"] < 3)).all()


def test_suite_listing_equals_the_cli(cli):
    ours = rocklab.records(suite="far_field")
    theirs = pd.DataFrame(json.loads(cli("records", "--suite", "far_field", "--json")))
    pd.testing.assert_frame_equal(ours, theirs)
    assert len(ours) == 44  # FEMA P695: 22 records × 2 components


def test_intensity_measures_equal_the_cli_json(cli):
    ours = rocklab.records(suite="near_field_pulse", ims=True, periods=[0.5, 1.0])
    theirs = pd.DataFrame(json.loads(
        cli("records", "--suite", "near_field_pulse", "--ims", "--periods", "0.5,1", "--json")))
    pd.testing.assert_frame_equal(ours[theirs.columns], theirs)
    # One column per period, in g, from the aligned lists.
    assert list(ours["sa(1)"]) == [sa[1] for sa in theirs["sa_g"]]
    assert (ours["pgd_m"] > 0).all() and (ours["arias_m_s"] > 0).all()
    # D5-95 holds D5-75 (both start at the 5 % point of the Husid curve).
    assert (ours["d5_95_s"] >= ours["d5_75_s"]).all()


def test_named_records_are_the_ones_listed(cli):
    ours = rocklab.records(names=["far_field/1a", "far_field/1b"], ims=True, periods=[1.0])
    assert list(ours["name"]) == ["far_field/1a", "far_field/1b"]
    theirs = pd.DataFrame(json.loads(
        cli("records", "far_field/1a", "far_field/1b", "--ims", "--periods", "1", "--json")))
    pd.testing.assert_frame_equal(ours[theirs.columns], theirs)
