"""Readers written to the formats' specifications, independent of TrainSim's writers: PNG
(ISO/IEC 15948: 8- and 16-bit greyscale and RGB, not interlaced), KITTI calib.txt, velodyne
.bin (float32 x y z intensity) and SemanticKITTI .label (uint32 class | instance << 16)."""
import struct
import zlib


def read_png(path):
    """(width, height, channels, rows): rows[v] is a list of width * channels sample values."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, idat = 8, b""
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert colour in (0, 2) and depth in (8, 16) and interlace == 0, (colour, depth)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    channels = 1 if colour == 0 else 3
    bpp = channels * depth // 8  # bytes per pixel, the filters' left neighbour distance
    stride = width * bpp
    raw = zlib.decompress(idat)
    prev = bytearray(stride)
    rows = []
    for v in range(height):
        f = raw[v * (stride + 1)]
        line = bytearray(raw[v * (stride + 1) + 1:(v + 1) * (stride + 1)])
        if f == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 0xFF
        elif f == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 0xFF
        elif f == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 0xFF
        elif f == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 0xFF
        else:
            assert f == 0, f"{path}: filter {f}"
        prev = line
        if depth == 8:
            rows.append(list(line))
        else:
            rows.append(list(struct.unpack(f">{stride // 2}H", bytes(line))))
    return width, height, channels, rows


def read_calib(path):
    """{key: [12 floats]} of a KITTI calib.txt."""
    out = {}
    for line in open(path):
        key, values = line.split(":", 1)
        out[key] = [float(x) for x in values.split()]
    return out


def read_velodyne(path):
    data = open(path, "rb").read()
    return [struct.unpack_from("<4f", data, 16 * i) for i in range(len(data) // 16)]


def read_labels(path):
    data = open(path, "rb").read()
    return list(struct.unpack(f"<{len(data) // 4}I", data))


def apply(m, p):
    """A 3 x 4 row-major matrix applied to a 3D point."""
    return [m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3]
            for r in range(3)]
