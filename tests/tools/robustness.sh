# Robustness (issue 12) as a user meets it: hostile headers fail fast under
# a memory limit with a message naming the file, damaged and odd inputs
# say what they are, and the fuzz targets' reproducers stay fixed.
. "$TOP/tests/tools/lib.sh"
plan 10
CR="$BIN/cloudrender"; TP="$BIN/terrainprep"; NB="$BIN/noisebake"
WX="$BIN/wxinterp"; MB="$BIN/mbfetch"; PATCH="$HELPERS/exrpatch"
DT0="$DATA/dem/n43.dt0"
# 800 MB of address space: the programs start and render small frames in
# it; the hostile headers claim 1 to 16 GiB.  Sanitizer builds reserve
# terabytes of shadow memory and cannot run under any such limit.
LIMIT_KB=800000
if sh -c 'ulimit -v '$LIMIT_KB' && "$1" --version' sh "$CR" >/dev/null 2>&1; then
	limited=1
else
	limited=0
fi
run_limited() { run sh -c 'ulimit -v '$LIMIT_KB' && exec "$@"' sh "$@"; }

# ---- hostile headers --------------------------------------------------
begin noise_volume_claiming_16_gib_fails_fast_naming_the_file
"$NB" -s 8 -d 8 -q -o "$T/n.exr" || bad "noisebake failed"
"$PATCH" "$T/n.exr" "$T/huge.exr" cloudscapeVolumeSize=1024,1024,1024 \
	dataWindow=0,0,1023,1048575 || bad "exrpatch failed"
"$PATCH" "$T/n.exr" "$T/big.exr" cloudscapeVolumeSize=512,512,512 \
	dataWindow=0,0,511,262143 || bad "exrpatch failed"
if [ $limited = 1 ]; then
	run_limited "$CR" --noise "$T/huge.exr" --size 16x9 -q -o "$T/a.png"
	expect_rc 1; expect_err "$T/huge.exr: cloudscapeVolumeSize 1024x1024x1024 is more voxels"
	run_limited "$CR" --noise "$T/big.exr" --size 16x9 -q -o "$T/a.png"
	expect_rc 1; expect_err "$T/big.exr: the header claims 512x262144 pixels"
	expect_no_file "$T/a.png"
	run_limited "$NB" --info "$T/big.exr"
	expect_rc 1; expect_err "$T/big.exr: the header claims"
	# the honest file still works under the same limit
	run_limited "$CR" --noise "$T/n.exr" --size 16x9 -q -o "$T/a.png"
	expect_rc 0; expect_file "$T/a.png"
	rm -f "$T/a.png"
else
	run "$CR" --noise "$T/big.exr" --size 16x9 -q -o "$T/a.png"
	expect_rc 1; expect_err "$T/big.exr: the header claims 512x262144 pixels"
fi
end

begin heightfield_claiming_268435455_columns_fails_fast_naming_the_file
if [ ! -f "$DT0" ]; then
	skip heightfield_claiming_268435455_columns_fails_fast_naming_the_file "$DT0 is absent"
else
	"$TP" -q --size 16x16 -o "$T/t.exr" "$DT0" || bad "terrainprep failed"
	"$PATCH" "$T/t.exr" "$T/wide.exr" dataWindow=0,0,268435454,0 compression=4 ||
		bad "exrpatch failed"
	cp "$T/t.json" "$T/wide.json"
	if [ $limited = 1 ]; then
		run_limited "$CR" --terrain "$T/wide.exr" --size 16x9 -q -o "$T/a.png"
	else
		run "$CR" --terrain "$T/wide.exr" --size 16x9 -q -o "$T/a.png"
	fi
	expect_rc 1; expect_no_file "$T/a.png"
	expect_err "$T/wide.exr: the header claims 268435455x1 pixels"
	expect_err "bytes can hold at most"
	end
fi

begin esri_grid_claiming_16000_squared_cells_fails_fast_naming_the_file
printf 'ncols 16000\nnrows 16000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n' >"$T/h.asc"
if [ $limited = 1 ]; then
	run_limited "$TP" -q --s-srs EPSG:32632 -o "$T/h.exr" "$T/h.asc"
else
	run "$TP" -q --s-srs EPSG:32632 -o "$T/h.exr" "$T/h.asc"
fi
expect_rc 1; expect_no_file "$T/h.exr"
expect_err "$T/h.asc: the header makes a 16000x16000 grid, more samples than 65 bytes can hold"
end

# ---- damaged and odd DEMs ----------------------------------------------
if [ ! -f "$DT0" ]; then
	skip terrainprep_names_the_damaged_tile_of_a_mosaic "$DT0 is absent"
	skip terrainprep_shows_gdal_warnings_unless_quiet "$DT0 is absent"
	skip terrainprep_reprojects_web_mercator_to_true_metres "$DT0 is absent"
else
	begin terrainprep_names_the_damaged_tile_of_a_mosaic
	cp "$DT0" "$T/bad.dt0"
	# one height of profile 65 changed: its checksum no longer verifies
	printf '\007' | dd of="$T/bad.dt0" bs=1 seek=20000 conv=notrunc 2>/dev/null
	run "$TP" -q --size 8x8 -o "$T/m.exr" "$DT0" "$T/bad.dt0"
	expect_rc 1; expect_no_file "$T/m.exr"
	expect_err "$T/bad.dt0 is damaged: The DTED driver has found a computed and read checksum that do not match at column 65"
	end

	begin terrainprep_shows_gdal_warnings_unless_quiet
	LC_ALL=C sed 's/WGS84/WGS72/' "$DT0" >"$T/w72.dt0"
	run "$TP" --size 8x8 -o "$T/w.exr" "$T/w72.dt0"
	expect_rc 0; expect_err "terrainprep: warning: The DTED file $T/w72.dt0 indicates WGS72"
	run "$TP" -q --size 8x8 -o "$T/w.exr" "$T/w72.dt0"
	expect_rc 0; [ -s "$T/err" ] && bad "-q still printed: $(head -c 200 "$T/err")"
	end

	begin terrainprep_reprojects_web_mercator_to_true_metres
	gdalwarp -q -t_srs EPSG:3857 -tr 1000 1000 -r bilinear "$DT0" "$T/merc.tif" ||
		bad "gdalwarp failed"
	run "$TP" --res 800 -o "$T/merc.exr" "$T/merc.tif"
	expect_rc 0
	expect_err "EPSG:3857 (WGS 84 / Pseudo-Mercator) is not in true metres here"
	# Web Mercator's scale at the tile's centre (43.5 N) is about
	# 1/cos(43.5 deg) = 1.379 (ellipsoid: 1.376 east, 1.381 north)
	k=$(sed -n 's/.*scale \([0-9.]*\)).*/\1/p' "$T/err")
	awk -v k="$k" 'BEGIN { exit !(k > 1.372 && k < 1.386) }' || bad "scale '$k', expected 1.379"
	grep -q '"epsg":[[:space:]]*32617' "$T/merc.json" || bad "not reprojected to UTM 17N (EPSG:32617)"
	grep -q '"x":[[:space:]]*800,' "$T/merc.json" || bad "pixel size is not the 800 m asked"
	# kept when asked for, with the true size said
	run "$TP" --t-srs EPSG:3857 --res 1000 -o "$T/keep.exr" "$DT0"
	expect_rc 0; expect_err "--t-srs EPSG:3857 (WGS 84 / Pseudo-Mercator) is not in true metres here"
	expect_err "about 725"
	# a true-metre CRS says nothing
	run "$TP" --t-srs EPSG:32617 --res 1000 -o "$T/utm.exr" "$DT0"
	expect_rc 0; grep -q 'true metres' "$T/err" && bad "UTM was called not true metres"
	end
fi

begin fuzz_dem_reproducer_origin_far_off_the_earth_fails_fast
# GDAL and PROJ took minutes on this one (gdalinfo too): timeout makes a
# hang a failure instead of a stuck suite
run timeout 60 "$TP" -q -o "$T/z.exr" "$TOP/tests/fixtures/fuzz/dem-origin-1e54-hangs-proj.tif"
expect_rc 1; expect_no_file "$T/z.exr"
expect_err "dem-origin-1e54-hangs-proj.tif: its georeferencing is off the Earth (origin 1.55883e+54"
end

begin fuzz_dem_reproducer_centre_off_the_earth_is_an_error
run "$TP" -q -o "$T/z.exr" "$TOP/tests/fixtures/fuzz/dem-centre-off-the-earth.tif"
expect_rc 1; expect_no_file "$T/z.exr"
expect_err "dem-centre-off-the-earth.tif: its georeferencing is off the Earth (origin -2.76779e+67"
end

# ---- messages --------------------------------------------------------
begin mbfetch_check_names_what_a_binary_file_looks_like
"$CR" --size 8x4 -q -o "$T/x.png" || bad "cloudrender failed"
"$NB" -s 4 -d 2 -q -o "$T/x.exr" || bad "noisebake failed"
printf 'not json\n' | gzip >"$T/x.gz"
for f in x.png:"a PNG image" x.exr:"an OpenEXR image" x.gz:"gzip-compressed data"; do
	run "$MB" --check "$T/${f%%:*}"
	expect_rc 7; expect_err "the response is not JSON: it looks like ${f#*:}"
	LC_ALL=C grep -q '[^[:print:][:space:]]' "$T/err" && bad "raw bytes on stderr for ${f%%:*}"
done
end

begin cloudrender_messages_say_what_is_wrong
run "$CR" --camera 46.9,7.4 -o "$T/c.png"
expect_rc 2; expect_err "--camera: expected three comma-separated numbers LAT,LON,ALT_M"
expect_err "got 2 in '46.9,7.4': the altitude is missing"
run "$CR" --size 100000x100000 -o "$T/c.png"
expect_rc 2; expect_err "image size 100000x100000 is too large: it would need about 490 GB"
"$WX" --template -o "$T/state.json" || bad "wxinterp failed"
printf '%s' '{"latitude":46.94,"longitude":7.44,"utc_offset_seconds":0,"elevation":540,"hourly_units":{"time":"unixtime","cloud_cover_low":"%","cloud_cover_mid":"%","cloud_cover_high":"%","precipitation":"mm","wind_speed_10m":"m/s","wind_direction_10m":"°"},"hourly":{"time":[1623628800,1623632400],"cloud_cover_low":[1,2],"cloud_cover_mid":[3,4],"cloud_cover_high":[5,6],"precipitation":[0,0],"wind_speed_10m":[1,2],"wind_direction_10m":[0,359]}}' >"$T/om.json"
run "$CR" --wx "$T/om.json" -o "$T/c.png"
expect_rc 1; expect_err "$T/om.json: this is an Open-Meteo response (hourly weather), not a cloudwx weather state"
expect_err "wxinterp --at TIME FILE"
run "$WX" --at 2021-06-14T01:00:00.5Z "$T/om.json"
expect_rc 1; expect_err "2021-06-14T01:00:00.5Z is outside the data"
expect_no_file "$T/c.png"
end
