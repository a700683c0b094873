#!/bin/sh
# BMPacsRoundTrip: the hospital's path from the command line against a real PACS, Debian's
# Orthanc, started here on loopback with its own storage and a free port: the scapula phantom's
# CT stored (bmsim pacs store), found by patient (pacs find), fetched into a new folder (pacs get),
# planned straight from the PACS (bmsim plan pacs://...) and from that folder alike, the plan's
# steps run with the results as DICOM
# (bmsim run --dicom), the Segmentation and Structured Report stored back, found in the CT's
# study by their modality and fetched again, also over DICOMweb (QIDO-RS, WADO-RS). A PACS that is down is an error naming it (exit 1),
# a get without its folder bad usage (exit 2).
#   sh TestPacsRoundTrip.sh BMSIM WORK_DIR
set -eu
BMSIM=$1
WORK=$2
rm -rf "$WORK"
mkdir -p "$WORK/orthanc"
fail() { echo "BMPacsRoundTrip: $*" >&2; exit 1; }
[ -x /usr/sbin/Orthanc ] || fail "/usr/sbin/Orthanc is not installed (Utilities/setup-debian.sh)"
port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
PORT=$(port)
HTTP=$(port)
PLUGIN=/usr/share/orthanc/plugins/libOrthancDicomWeb.so
[ -r $PLUGIN ] || fail "$PLUGIN is not installed (orthanc-dicomweb, Utilities/setup-debian.sh)"
cat > "$WORK/orthanc/orthanc.json" <<EOF
{"Name": "BMTEST", "StorageDirectory": "$WORK/orthanc/storage", "IndexDirectory": "$WORK/orthanc/storage",
 "DicomAet": "ORTHANC", "DicomPort": $PORT, "HttpServerEnabled": true, "HttpPort": $HTTP,
 "RemoteAccessAllowed": false, "AuthenticationEnabled": false, "DicomCheckCalledAet": true,
 "Plugins": ["$PLUGIN"], "DicomWeb": {"Enable": true, "Root": "/dicom-web/"}, "ConcurrentJobs": 1,
 "DicomModalities": {"bm": ["BMSIM", "127.0.0.1", $(port)]}}
EOF
/usr/sbin/Orthanc "$WORK/orthanc/orthanc.json" > "$WORK/orthanc/orthanc.log" 2>&1 &
ORTHANC_PID=$!
trap 'kill $ORTHANC_PID 2>/dev/null; wait $ORTHANC_PID 2>/dev/null || true' EXIT
i=0
until python3 -c "import socket; [socket.create_connection(('127.0.0.1', p), 1) for p in ($PORT, $HTTP)]" 2>/dev/null; do
  i=$((i + 1))
  [ $i -lt 150 ] || fail "Orthanc did not listen on port $PORT (see $WORK/orthanc/orthanc.log)"
  sleep 0.2
done
SERVER="ORTHANC@127.0.0.1:$PORT"

# The phantom's CT into the PACS.
"$BMSIM" phantom scapula --pixel-mm 1.0 --slice-mm 2.0 --out "$WORK/phantom" --quiet > /dev/null
"$BMSIM" pacs store --server "$SERVER" "$WORK"/phantom/*.dcm || fail "pacs store failed"

# Found by the patient's ID, fetched into a new folder.
"$BMSIM" pacs find --server "$SERVER" --patient-id BM-PHANTOM > "$WORK/find.txt" || fail "pacs find failed"
cat "$WORK/find.txt"
grep -q "^1 series" "$WORK/find.txt" || fail "pacs find did not find the one CT series"
SERIES=$(sed -n 's/.* series \([0-9.]*\)$/\1/p' "$WORK/find.txt")
STUDY=$(sed -n 's/.* study \([0-9.]*\) | series .*/\1/p' "$WORK/find.txt")
[ -n "$SERIES" ] && [ -n "$STUDY" ] || fail "no study and series UID in pacs find's answer"
"$BMSIM" pacs get --server "$SERVER" --series "$SERIES" --out "$WORK/fetched" || fail "pacs get failed"
n=$(ls "$WORK/fetched" | wc -l)
m=$(ls "$WORK"/phantom/*.dcm | wc -l)
[ "$n" -eq "$m" ] || fail "pacs get wrote $n files of the $m stored"

# Planned straight from the PACS (bmsim plan pacs://...: the series fetched into plan/ct), the
# same plan as from the fetched folder; its steps run, the results written as DICOM.
"$BMSIM" plan "pacs://$SERVER/$SERIES" --out "$WORK/plan" --quiet > /dev/null ||
  fail "bmsim plan pacs://$SERVER/$SERIES failed"
[ "$(ls "$WORK/plan/ct" | wc -l)" -eq "$m" ] || fail "bmsim plan pacs:// did not keep the series in plan/ct"
"$BMSIM" plan "$WORK/fetched" --out "$WORK/plan-folder" --quiet > /dev/null || fail "bmsim plan on the fetched CT failed"
for key in version_3d_deg inclination_deg; do
  a=$(python3 -c "import json; print(json.load(open('$WORK/plan/plan_report.json'))['measurements']['$key'])")
  b=$(python3 -c "import json; print(json.load(open('$WORK/plan-folder/plan_report.json'))['measurements']['$key'])")
  [ "$a" = "$b" ] || fail "the plan from the PACS gives $key $a, from the fetched folder $b"
done
# A series the PACS does not hold: named, and no plan folder left.
set +e
"$BMSIM" plan "pacs://$SERVER/1.2.3.4" --out "$WORK/plan-none" --quiet > "$WORK/none.txt" 2>&1
rc=$?
set -e
[ $rc -eq 1 ] && grep -q "no series 1.2.3.4" "$WORK/none.txt" || fail "plan of an unknown PACS series: $rc, $(cat "$WORK/none.txt")"
[ ! -e "$WORK/plan-none" ] || fail "a failed plan from the PACS left $WORK/plan-none"
"$BMSIM" run "$WORK/plan/plan.json" --voxmap-resolution 96 --no-report --dicom --out "$WORK/run" > /dev/null ||
  fail "bmsim run --dicom on the plan failed"

# Stored back beside the CT, found in its study by modality, fetched again.
"$BMSIM" pacs store --server "$SERVER" "$WORK/run/dicom/reamed-bone.seg.dcm" "$WORK/run/dicom/plan.sr.dcm" ||
  fail "pacs store of the results failed"
for modality in SEG SR; do
  "$BMSIM" pacs find --server "$SERVER" --study "$STUDY" --modality $modality > "$WORK/find-$modality.txt"
  grep -q "^1 series" "$WORK/find-$modality.txt" || fail "no $modality series in the CT's study: $(cat "$WORK/find-$modality.txt")"
  uid=$(sed -n 's/.* series \([0-9.]*\)$/\1/p' "$WORK/find-$modality.txt")
  "$BMSIM" pacs get --server "$SERVER" --study "$STUDY" --series "$uid" --out "$WORK/back-$modality" ||
    fail "pacs get of the $modality failed"
  [ "$(ls "$WORK/back-$modality" | wc -l)" -eq 1 ] || fail "the $modality series did not come back as one file"
  cmp -s "$(ls "$WORK"/back-$modality/*)" /dev/null && fail "the $modality came back empty"
done
# The same PACS through DICOMweb: the SR stored over DIMSE is found (QIDO-RS) and fetched
# (WADO-RS) through it.
WEB="http://127.0.0.1:$HTTP/dicom-web"
"$BMSIM" pacs find --server "$WEB" --study "$STUDY" --modality SR > "$WORK/find-web.txt" || fail "pacs find over DICOMweb failed"
grep -q "^1 series" "$WORK/find-web.txt" || fail "no SR series over DICOMweb: $(cat "$WORK/find-web.txt")"
uid=$(sed -n 's/.* series \([0-9.]*\)$/\1/p' "$WORK/find-web.txt")
"$BMSIM" pacs get --server "$WEB" --series "$uid" --out "$WORK/back-web" || fail "pacs get over DICOMweb failed"
# Both name the file by its SOP Instance UID: the same instance.
[ "$(ls "$WORK/back-web")" = "$(ls "$WORK/back-SR")" ] ||
  fail "over DICOMweb $(ls "$WORK/back-web"), over DIMSE $(ls "$WORK/back-SR")"
if command -v dciodvfy > /dev/null; then
  for f in "$WORK"/back-SEG/* "$WORK"/back-SR/*; do
    if dciodvfy "$f" 2>&1 | grep -q "^Error"; then fail "dciodvfy finds errors in the fetched $f"; fi
  done
fi

# Failures: a PACS that is down (exit 1, named), a get without its folder (exit 2).
set +e
"$BMSIM" pacs find --server "ORTHANC@127.0.0.1:$(port)" --timeout 2 > "$WORK/down.txt" 2>&1
rc=$?
set -e
[ $rc -eq 1 ] || fail "pacs find against a PACS that is down exited $rc"
grep -q "no association" "$WORK/down.txt" || fail "pacs find against a PACS that is down: $(cat "$WORK/down.txt")"
set +e
"$BMSIM" pacs get --server "$SERVER" --series "$SERIES" > /dev/null 2>&1
rc=$?
set -e
[ $rc -eq 2 ] || fail "pacs get without --out exited $rc"
echo "BMPacsRoundTrip: stored, found, fetched, planned, results stored back and fetched"
