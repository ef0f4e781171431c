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
