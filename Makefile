# The two commands of the README:
#   make run   installs what is missing, builds, and opens the viewer when a display exists
#              (DISPLAY or WAYLAND_DISPLAY), otherwise renders the default scene to meadow.png
#   make test  installs what is missing, then fmt, clippy and the whole test suite on lavapipe
CARGO ?= cargo

.PHONY: deps run test test-generic goldens build soak pictures bench-docs cli-docs

deps:
	@./scripts/install-deps.sh

build: deps
	$(CARGO) build --release

run: build
	@if [ -n "$$DISPLAY$$WAYLAND_DISPLAY" ]; then \
		./target/release/meadow view; \
	else \
		./target/release/meadow render --out meadow.png; \
	fi

test: deps
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --all-targets -- -D warnings
	$(CARGO) test --release
	# 1 000-frame soaks of the viewer's own lifecycle (swapchain re-creations, frame ring,
	# deferred deletions), culled, by brute force and with the stateful Verlet blades under the
	# Perlin wind: no memory or live-object growth.
	FRAMES=1000 ./scripts/soak.sh
	FRAMES=1000 ./scripts/soak.sh --brute-force
	FRAMES=1000 ./scripts/soak.sh --animation verlet --wind-field perlin
	FRAMES=1000 ./scripts/soak.sh --wind-field fluid

# The whole test suite again on the generic backend profile (vk::profile: each resource bound once,
# none of the lavapipe profile's twins), pictures at the same golden tolerances; the soaks stay on
# the lavapipe profile (scripts/soak.sh forces it). Not part of `make test`: it doubles its time.
test-generic: deps
	MEADOW_PROFILE=generic $(CARGO) test --release

# Regenerate tests/golden/*.png from the current renderer (review the pictures before committing).
goldens: deps
	MEADOW_UPDATE_GOLDENS=1 $(CARGO) test --release --test golden

# Regenerate docs/cli.md from the clap definitions (tests/docs.rs fails while it differs).
cli-docs:
	MEADOW_UPDATE_DOCS=1 $(CARGO) test --release --test docs the_cli_reference_is_generated_from_the_parser

# The viewer for 10 000 frames with swapchain re-creations: fails on resident-memory growth over
# 4 MiB or any growth of live Vulkan objects (scripts/soak.sh; FRAMES=N for another length).
soak: build
	FRAMES=$${FRAMES:-10000} ./scripts/soak.sh

# The pictures of README.md and docs/ that renders make (a few minutes on lavapipe), each with the
# command written beside it in the docs; the viewer's screenshots under Xvfb
# (scripts/viewer/showcase.txt writes docs/viewer-force.png and docs/viewer.png).
MEADOW ?= ./target/release/meadow
WIND_FEATURES = --blades 60000 --size 960x540 --camera 0,5,7,0,-42 --time 1.5 --calm=-5,-4,-1,0 \
	--source 3,-1,0.25,2 --collider sphere:0,0.2,2.5,0.45 --attenuation blade --cluster-size 0.5
LANDSCAPE = --field infinite --camera -15,22,60,0,-18 --size 960x540 --fog 0.002
FAR_FIELD = --field infinite --view-distance 2000 --fog 0.001 --size 960x540
FAR_CLOSE = --field infinite --view-distance 60 --blade-distance 6 --camera 0,1.5,0,0,-12 --fog 0.001 --no-gusts \
	--size 640x360
FAR_GUST = --field infinite --camera landscape --view-distance 1500 --fog 0.0005 --no-gusts --wind 0,0.05 \
	--source 0,-60,40,1,0,-60 --debug-view force --size 640x360
pictures: build
	$(MEADOW) render --blades 1000000 --segments 4 --validation --out docs/meadow-1m.png
	$(MEADOW) render --out docs/landscape-default.png
	$(MEADOW) render --field infinite --out docs/prairie-field.png
	$(MEADOW) render --field infinite --debug-view lod --out docs/prairie-field-lod.png
	$(MEADOW) render $(WIND_FEATURES) --wind 0,0.9 --out docs/wind-features.png
	$(MEADOW) render $(WIND_FEATURES) --wind 0,0.5 --debug-view force --out docs/wind-features-force.png
	$(MEADOW) render --blades 60000 --wind-field fluid --debug-view wind --wind 0,0.3 --collider sphere:0,0.5,0,1.2 \
		--source -2,-3,0.6,0.8 --time 6 --camera 0,10,6.5,0,-62 --size 960x540 --out docs/wind-view-fluid.png
	$(MEADOW) render --field infinite --wind-field perlin --debug-view wind --camera 0,30,30,0,-50 --time 2 \
		--size 960x540 --fog 0.004 --out docs/wind-view-perlin.png
	$(MEADOW) render $(LANDSCAPE) --out docs/landscape-procedural.png
	$(MEADOW) render $(LANDSCAPE) --heightmap assets/landscape/heightmap.png --cover assets/landscape/cover.png \
		--terrain-scale 200,12,200 --out docs/landscape-maps.png
	$(MEADOW) render --field infinite --clumps 1.5 --camera 0,3,0,0,-25 --size 960x540 --out docs/landscape-clumps.png
	$(MEADOW) render --field infinite --flowers 20 --camera 0,3,0,0,-25 --size 960x540 --out docs/landscape-flowers.png
	$(MEADOW) render --field infinite --camera 20,9,40,30,-22 --size 960x540 --fog 0.002 --heightmap assets/landscape/heightmap.png \
		--cover assets/landscape/cover.png --terrain-scale 200,12,200 --flowers 100 --out docs/landscape-meadows.png
	for t in 1 2.5 6 14; do $(MEADOW) render --blades 20000 --camera 2.2,1.1,1.0,62,-28 --size 320x240 \
		--collider sphere:-2.5,0.35,0,0.45,1.5,0,0 --recovery-s 8 --time $$t --out docs/trail-$$t.png || exit 1; done
	xvfb-run -a -s "-screen 0 1280x720x24" $(MEADOW) view --blades 100000 --size 960x540 --script scripts/viewer/showcase.txt
	xvfb-run -a -s "-screen 0 1280x720x24" $(MEADOW) view $(FAR_FIELD) --script scripts/viewer/far-field.txt
	for t in 0 2 4 6; do $(MEADOW) render $(FAR_GUST) --time $$t --out docs/far-gust-$$t.png || exit 1; done
	$(MEADOW) render $(FAR_CLOSE) --out docs/far-fade-dither.png
	$(MEADOW) render $(FAR_CLOSE) --fade blend --out docs/far-fade-blend.png
	$(MEADOW) render $(FAR_CLOSE) --flowers 40 --out docs/far-flowers.png

# The benchmark results and charts in docs/ (docs/benchmarks.md, docs/gpu-timing.md): over half an
# hour on lavapipe, most of it the thesis preset. Run it on a quiet machine.
bench-docs: build
	$(MEADOW) bench --preset thesis --out docs/bench-thesis
	$(MEADOW) bench --preset lod --out docs/bench-lod
	$(MEADOW) bench --preset msaa --out docs/bench-msaa
	$(MEADOW) bench --preset response --out docs/bench-response
	$(MEADOW) bench --preset plants --out docs/bench-plants
	$(MEADOW) bench --preset interaction --out docs/bench-interaction
	$(MEADOW) overhead --out docs/overhead
	$(MEADOW) timing --trace docs/timing/trace.json --out docs/timing
