from pathlib import Path

import pytest

import rocklab
from conftest import REPO

STUDIES = sorted((REPO / "studies").glob("*.ron"))


@pytest.mark.parametrize("path", STUDIES, ids=[p.stem for p in STUDIES])
def test_unedited_study_saves_byte_for_byte(path):
    assert rocklab.Study.load(path).to_ron() == path.read_text()


def test_edit_round_trips(tmp_path):
    s = rocklab.Study.load(REPO / "studies" / "default.ron")
    s["name"] = "edited"
    s["duration"] = 12.5
    saved = s.save(tmp_path / "edited.ron")
    back = rocklab.Study.load(saved)
    assert back == s
    assert back["duration"] == 12.5
    # The header comment of the file it came from is kept.
    assert saved.read_text().startswith("// The built-in default study")


def test_invalid_edit_is_refused_with_the_field():
    s = rocklab.Study.load("default")
    s["duration"] = -1.0
    with pytest.raises(rocklab.StudyError, match="duration"):
        s.to_ron()


def test_bad_ron_names_line_and_field():
    text = (REPO / "studies" / "default.ron").read_text().replace("duration", "durration")
    with pytest.raises(rocklab.StudyError) as e:
        rocklab.Study.from_ron(text)
    # Line 25, column 5 of the text: where the misspelt field is.
    assert str(e.value).startswith("<study text>:25:5: durration:")
    assert "hint" in str(e.value)
