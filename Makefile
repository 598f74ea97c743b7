# The two commands of the README:
#   make run   installs what is missing, builds, and opens the viewer when a display exists
#              (DISPLAY or WAYLAND_DISPLAY), otherwise renders the default scene to meadow.png
#   make test  installs what is missing, then fmt, clippy and the whole test suite on lavapipe
CARGO ?= cargo

.PHONY: deps run test goldens build soak

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
	# deferred deletions), culled and by brute force: no memory or live-object growth.
	FRAMES=1000 ./scripts/soak.sh
	FRAMES=1000 ./scripts/soak.sh --brute-force

# Regenerate tests/golden/*.png from the current renderer (review the pictures before committing).
goldens: deps
	MEADOW_UPDATE_GOLDENS=1 $(CARGO) test --release --test golden

# The viewer for 10 000 frames with swapchain re-creations: fails on resident-memory growth over
# 4 MiB or any growth of live Vulkan objects (scripts/soak.sh; FRAMES=N for another length).
soak: build
	FRAMES=$${FRAMES:-10000} ./scripts/soak.sh
