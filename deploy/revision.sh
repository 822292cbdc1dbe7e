# Sourced by deploy/build-image.sh and deploy/test-image.sh: the source revision an image is
# built from (its org.opencontainers.image.revision label), "-dirty" when tracked or
# unignored files differ from HEAD, "unknown" outside a git checkout.
source_revision() {
    local rev
    rev=$(git -C "$(dirname "${BASH_SOURCE[0]}")/.." rev-parse --short HEAD 2>/dev/null) || {
        echo unknown
        return
    }
    [ -n "$(git -C "$(dirname "${BASH_SOURCE[0]}")/.." status --porcelain 2>/dev/null)" ] && rev+=-dirty
    echo "$rev"
}
