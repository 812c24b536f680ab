# nhlab in a container. Three stages: node builds the page, cargo builds the binary (which
# embeds the page), and the runtime image holds only that binary, run as a non-root user on
# 0.0.0.0:8080.
#   docker build -t nhlab . && docker run --rm -p 8080:8080 nhlab
#   then open http://localhost:8080

FROM node:22-bookworm-slim AS web
WORKDIR /src/web
# Manifests first: the npm layer is reused until they change.
COPY web/package.json web/package-lock.json ./
RUN npm ci --no-audit --no-fund
COPY web/ ./
RUN npm run build

FROM rust:1.95-bookworm AS build
WORKDIR /src
# The dependencies in a layer of their own, rebuilt only when a manifest or Cargo.lock
# changes: the workspace's manifests with stub sources (every member needs its targets, and
# core's declared bench its file), built once.
COPY Cargo.toml Cargo.lock rustfmt.toml ./
COPY core/Cargo.toml core/
COPY server/Cargo.toml server/
COPY tests/Cargo.toml tests/
COPY python/Cargo.toml python/
RUN mkdir -p core/src core/benches server/src tests/src python/src \
    && touch core/src/lib.rs server/src/lib.rs tests/src/lib.rs python/src/lib.rs \
    && echo 'fn main() {}' > core/benches/steps.rs \
    && echo 'fn main() {}' > server/src/main.rs \
    && echo 'fn main() {}' > server/build.rs \
    && cargo build --release --locked -p nhlab-server \
    && rm -rf core/src core/benches server/src server/build.rs tests/src python/src
COPY core/ core/
COPY server/ server/
COPY tests/ tests/
COPY python/ python/
COPY web/ web/
COPY --from=web /src/web/dist web/dist
# The page is built already: server/build.rs embeds web/dist as it is instead of running npm.
ENV NHLAB_SKIP_WEB_BUILD=1
# The copied sources may be older than the stubs' build: touched, they are rebuilt.
RUN find core server tests python -name '*.rs' -exec touch {} + \
    && cargo build --release --locked -p nhlab-server \
    && cp target/release/nhlab /usr/local/bin/nhlab

FROM debian:bookworm-slim
RUN groupadd --system --gid 10001 nhlab \
    && useradd --system --uid 10001 --gid 10001 --no-create-home --shell /usr/sbin/nologin nhlab
COPY --from=build /usr/local/bin/nhlab /usr/local/bin/nhlab
# Numeric, so the host and Kubernetes' runAsNonRoot can check it is not root.
USER 10001:10001
ENV NHLAB_ADDR=0.0.0.0:8080
EXPOSE 8080
# GET /health over bash's /dev/tcp (the image has no curl), on NHLAB_ADDR's port.
HEALTHCHECK --interval=30s --timeout=5s --start-period=5s --retries=3 \
    CMD ["bash", "-c", "exec 3<>/dev/tcp/127.0.0.1/${NHLAB_ADDR##*:} && printf 'GET /health HTTP/1.0\\r\\nHost: localhost\\r\\n\\r\\n' >&3 && head -n 1 <&3 | grep -q ' 200 '"]
ENTRYPOINT ["/usr/local/bin/nhlab"]
