"""The attitude as CCSDS Attitude Data Messages (``tumble run --aem``), read back by an
independent reader, ccsds-ndm (the test extra installs it).

ccsds-ndm 3.1 parses an APM of ADM version 2 into its NDM/XML 4.0 model; its builder of an AEM
of version 2 in KVN fails (it looks for the version-1 field of a quaternion line), so the AEM
is read with its KVN tokenizer and its message dispatcher, which find the message's type and
version, its metadata and its data lines; the data line's items are in the order of table 4-4
of the standard (EPOCH Q1 Q2 Q3 QC).
"""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import numpy as np
import pytest
import xarray as xr
from files import EXAMPLES, write
from typer.testing import CliRunner

from tumble.cli import app
from tumble.io.ccsds import epochs
from tumble.rotations import quat_to_matrix

runner = CliRunner()


def _short_envisat(tmp_path):
    """Envisat over 2 h, 9 samples, the full motion only."""
    text = (EXAMPLES / "ob_envisat_like.toml").read_text()
    for old, new in (("t_end_days = 365.0", "t_end_days = 0.08333333333333333"),
                     ("samples = 366", "samples = 9"),
                     ('methods = ["averaged"]', 'methods = ["full"]')):  # fmt: skip
        assert old in text
        text = text.replace(old, new)
    return write(tmp_path, text, "envisat_short.toml")


def test_the_aem_and_apm_read_back_with_the_runs_quaternions_and_epochs(tmp_path):
    pytest.importorskip("ccsds_ndm")
    from ccsds_ndm.kvn_parser import dispatch_document
    from ccsds_ndm.kvn_tokenizer import PackedDataLine, tokenize
    from ccsds_ndm.ndm_kvn_io import NdmKvnIo

    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(_short_envisat(tmp_path)), "-o", str(out), "--aem"])
    assert res.exit_code == 0, res.output
    ds = xr.open_dataset(out / "full.nc", engine="scipy")
    q = np.column_stack([ds[c].values for c in ("q0", "q1", "q2", "q3")])
    start = datetime(2013, 9, 25, tzinfo=UTC)
    expected = [start + timedelta(seconds=float(t)) for t in ds["t_s"].values]

    doc = dispatch_document(tokenize((out / "full.aem").read_text()))
    assert doc.ndm_type.name == "AEMv2"
    header = {line.key: line.value for line in doc.header if hasattr(line, "key")}
    assert header["CCSDS_AEM_VERS"] == "2.0"
    (segment,) = doc.segments
    meta = {line.key: line.value for line in segment.meta if hasattr(line, "key")}
    assert meta["REF_FRAME_A"] == "TEME" and meta["REF_FRAME_B"] == "SC_BODY_1"
    assert meta["TIME_SYSTEM"] == "UTC" and meta["ATTITUDE_TYPE"] == "QUATERNION"
    rows = [line.tokens for line in segment.data if isinstance(line, PackedDataLine)]
    assert len(rows) == ds.sizes["tau"] == 9
    read = np.array([[float(x) for x in row[1:]] for row in rows])  # Q1 Q2 Q3 QC
    np.testing.assert_allclose(read[:, 3], q[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(read[:, :3], q[:, 1:], rtol=0, atol=1e-12)
    tags = [datetime.fromisoformat(row[0][:26]).replace(tzinfo=UTC) for row in rows]
    assert all(abs((a - b).total_seconds()) < 1e-6 for a, b in zip(tags, expected, strict=True))
    assert meta["START_TIME"] == rows[0][0] and meta["STOP_TIME"] == rows[-1][0]

    apm = NdmKvnIo().from_path(out / "initial.apm")  # the whole message, NDM/XML 4.0 model
    data = apm.body.segment.data
    assert datetime.fromisoformat(data.epoch[:26]).replace(tzinfo=UTC) == start
    (quat,) = data.quaternion_state
    # (its builder leaves the block's REF_FRAME_A and REF_FRAME_B unset: not checked here)
    got = quat.quaternion
    np.testing.assert_allclose([got.qc, got.q1, got.q2, got.q3], q[0], rtol=0, atol=1e-12)
    manifest = (out / "manifest.json").read_text()
    assert '"full.aem"' in manifest and '"initial.apm"' in manifest


def test_tumbles_quaternion_is_the_adms_from_inertial_to_body():
    """Annex F2: M_BA, which takes frame A's components (inertial) to frame B's (body), of
    Q1 Q2 Q3 QC is the transpose of tumble's R(q) (body → inertial) with Q = (q1, q2, q3),
    QC = q0."""
    rng = np.random.default_rng(7)
    for q in rng.normal(size=(20, 4)):
        q /= np.linalg.norm(q)
        qc, q1, q2, q3 = q
        m_ba = np.array([
            [q1*q1 - q2*q2 - q3*q3 + qc*qc, 2*(q1*q2 + q3*qc), 2*(q1*q3 - q2*qc)],
            [2*(q1*q2 - q3*qc), -q1*q1 + q2*q2 - q3*q3 + qc*qc, 2*(q2*q3 + q1*qc)],
            [2*(q1*q3 + q2*qc), 2*(q2*q3 - q1*qc), -q1*q1 - q2*q2 + q3*q3 + qc*qc],
        ])  # fmt: skip
        np.testing.assert_allclose(m_ba, quat_to_matrix(q).T, rtol=0, atol=1e-15)


def test_epochs_carry_the_seconds_to_the_nanosecond():
    tags = epochs("2013-12-31T23:59:59.5Z", np.array([0.0, 0.5, 86400.25]))
    assert tags == [
        "2013-12-31T23:59:59.500000000",
        "2014-01-01T00:00:00.000000000",  # across the year, the carry of the half second
        "2014-01-01T23:59:59.750000000",
    ]


@pytest.mark.parametrize(
    ("scenario", "words"),
    [("ob_envisat_like.toml", 'add "full"'), ("a3_positive.toml", "no absolute epoch")],
)
def test_a_run_without_attitude_or_epoch_is_refused_before_it_runs(tmp_path, scenario, words):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(EXAMPLES / scenario), "-o", str(out), "--aem"])
    assert res.exit_code == 2, res.output
    assert words in res.output and "--aem" in res.output
    assert not out.exists() or not any(out.iterdir())
