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
COPY . .
COPY --from=web /src/web/dist web/dist
# The page is built already: server/build.rs embeds web/dist as it is instead of running npm.
ENV NHLAB_SKIP_WEB_BUILD=1
RUN cargo build --release --locked -p nhlab-server \
    && cp target/release/nhlab /usr/local/bin/nhlab

FROM debian:bookworm-slim
RUN groupadd --system --gid 10001 nhlab \
    && useradd --system --uid 10001 --gid 10001 --no-create-home --shell /usr/sbin/nologin nhlab
COPY --from=build /usr/local/bin/nhlab /usr/local/bin/nhlab
# Numeric, so the host and Kubernetes' runAsNonRoot can check it is not root.
USER 10001:10001
ENV NHLAB_ADDR=0.0.0.0:8080
EXPOSE 8080
ENTRYPOINT ["/usr/local/bin/nhlab"]
