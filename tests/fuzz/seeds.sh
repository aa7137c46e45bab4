#!/bin/sh
# Makes the fuzz targets' seed corpora in OUT/<target>/ (not in the tree):
# the hand-written seeds of tests/fuzz/seeds/ (dem/tiff-60000-bands: a
# one-pixel GeoTIFF of 60000 bands, whose warp once took minutes), the real data of
# ../shared/data (skipped with a message when absent) and files the built
# tools write from it.  Usage: tests/fuzz/seeds.sh BUILD_DIR OUT
set -u
B=${1:?build dir}; OUT=${2:?output dir}
top=$(cd "$(dirname "$0")/../.." && pwd)
BIN="$top/$B/bin"
DATA=${DATA:-$top/../shared/data}
CAPTURE=$DATA/weather/meteoblue-basic-clouds-solar-1h.json
DT0=$DATA/dem/n43.dt0
rm -rf "$OUT"
for t in wx provider noise_exr terrain dem text png; do mkdir -p "$OUT/$t"; done
for d in "$top"/tests/fuzz/seeds/*/; do
	cp "$d"* "$OUT/$(basename "$d")/" 2>/dev/null
done
tmp=$(mktemp -d "${TMPDIR:-/tmp}/cs-seeds.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
q() { "$@" >/dev/null 2>&1 || echo "seeds: '$*' failed (seed left out)" >&2; }
# a byte (0..255) followed by a file: the DEM target's file-name selector
prefixed() { # BYTE FILE OUT
	printf "\\$(printf %03o "$1")" >"$3" && cat "$2" >>"$3"
}

# files the tools write without real data
q "$BIN/wxinterp" --template -o "$OUT/wx/template.json"
q "$BIN/wxinterp" --template --set layer.low=cumulonimbus --set precipitation=8 \
	--set convective=6 --set temperature=-3 --set snow=0.9 -o "$OUT/wx/storm.json"
q "$BIN/noisebake" -s 4 -d 2 -q -o "$OUT/noise_exr/n4x2.exr"
q "$BIN/noisebake" -s 6 -d 3 --seed 5 --float -q -o "$OUT/noise_exr/n6x3-float.exr"
q "$BIN/noisebake" -s 8 --freq 1,2,3,4 --octaves 1,1,2,2 -q -o "$OUT/noise_exr/n8.exr" \
	--preview "$OUT/png/noise-preview.png"
q "$BIN/cloudrender" --size 16x9 -q -o "$OUT/png/sky.png"

if [ -f "$CAPTURE" ]; then
	cp "$CAPTURE" "$OUT/provider/meteoblue-capture.json"
	q "$BIN/wxinterp" --at 2024-10-07T12:30Z "$CAPTURE" -o "$OUT/wx/capture-1230.json"
	q "$BIN/wxinterp" --from 2024-10-07T00:00Z --to 2024-10-07T05:00Z "$CAPTURE" \
		-o "$OUT/wx/capture-series.jsonl"
	q "$BIN/wxinterp" --at 2024-10-08T06:00Z --far "$CAPTURE" --far-name far \
		--pretty "$CAPTURE" -o "$OUT/wx/capture-far-pretty.json"
else
	echo "seeds: $CAPTURE is absent: no real weather seeds" >&2
fi
if [ -f "$DT0" ]; then
	prefixed 2 "$DT0" "$OUT/dem/n43.dt0"
	for a in "$DATA"/dem/*.asc; do prefixed 1 "$a" "$OUT/dem/$(basename "$a")"; done
	q gdal_translate -q -outsize 8 8 "$DT0" "$tmp/small.tif"
	[ -f "$tmp/small.tif" ] && prefixed 3 "$tmp/small.tif" "$OUT/dem/small.tif"
	q gdalwarp -q -t_srs EPSG:3857 -ts 8 8 "$DT0" "$tmp/merc.tif"
	[ -f "$tmp/merc.tif" ] && prefixed 3 "$tmp/merc.tif" "$OUT/dem/webmercator.tif"
	q gdal_translate -q -of XYZ -outsize 5 5 "$DT0" "$tmp/small.xyz"
	[ -f "$tmp/small.xyz" ] && prefixed 4 "$tmp/small.xyz" "$OUT/dem/small.xyz"
	# heightfields: the sidecar's length (2 bytes, little endian), it, the EXR
	for s in 8x8 5x3; do
		q "$BIN/terrainprep" -q --size "$s" -o "$tmp/t$s.exr" "$DT0" \
			--hillshade "$OUT/png/hillshade-$s.png"
		[ -f "$tmp/t$s.json" ] || continue
		n=$(wc -c <"$tmp/t$s.json")
		printf "\\$(printf %03o $((n % 256)))\\$(printf %03o $((n / 256)))" >"$OUT/terrain/t$s"
		cat "$tmp/t$s.json" "$tmp/t$s.exr" >>"$OUT/terrain/t$s"
	done
	# PNGs of other kinds: palette, 16-bit grey, interlaced, with alpha
	if command -v pnmtopng >/dev/null 2>&1 && [ -f "$OUT/png/hillshade-8x8.png" ]; then
		pngtopnm "$OUT/png/hillshade-8x8.png" >"$tmp/h.pgm" 2>/dev/null
		q sh -c "pnmdepth 65535 '$tmp/h.pgm' | pnmtopng >'$OUT/png/grey16.png'"
		q sh -c "pnmtopng -interlace '$tmp/h.pgm' >'$OUT/png/interlaced.png'"
		q sh -c "pnmtopng -alpha='$tmp/h.pgm' '$tmp/h.pgm' >'$OUT/png/alpha.png'"
		q sh -c "pngtopnm '$OUT/png/sky.png' | pnmquant 4 | pnmtopng >'$OUT/png/palette.png'"
	fi
else
	echo "seeds: $DT0 is absent: no DEM, heightfield or hillshade seeds" >&2
fi
# empty files count as nothing: drop them
find "$OUT" -type f -size 0 -delete
exit 0
