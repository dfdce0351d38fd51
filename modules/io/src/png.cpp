#include "trainsim/io/png.hpp"

#include <cstring>
#include <vector>

#include <png.h>
#include <zlib.h>

#include <fmt/format.h>

#include "trainsim/core/error.hpp"

namespace trainsim::io {
namespace {

// libpng reports errors through longjmp; these callbacks turn them into exceptions raised
// after png_destroy_* has run, never across libpng's frames.
struct PngContext {
  std::string out;
  std::string error;
};

void onError(png_structp png, png_const_charp message) {
  auto* ctx = static_cast<PngContext*>(png_get_error_ptr(png));
  ctx->error = message;
  png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}
void onWrite(png_structp png, png_bytep data, png_size_t length) {
  auto* ctx = static_cast<PngContext*>(png_get_io_ptr(png));
  ctx->out.append(reinterpret_cast<const char*>(data), length);
}
void onFlush(png_structp) {}

std::string encode(int width, int height, int color_type, int depth, const std::uint8_t* rows,
                   std::size_t row_bytes, PngContent content) {
  PngContext ctx;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, onError, onWarning);
  if (!png)
    throw RuntimeError("png: cannot create the encoder");
  png_infop info = png_create_info_struct(png);
  // NOLINTNEXTLINE(cert-err52-cpp): libpng's error protocol
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw RuntimeError(fmt::format("png: {}", ctx.error.empty() ? "encoding failed" : ctx.error));
  }
  png_set_write_fn(png, &ctx, onWrite, onFlush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), depth,
               color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  switch (content) {
    case PngContent::kImage:
      png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
      png_set_compression_level(png, 4);
      break;
    case PngContent::kMeasurement:
      png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
      png_set_compression_level(png, 4);
      break;
    case PngContent::kLabels:
      png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
      png_set_compression_level(png, 4);
      if (depth == 8)  // ids in one byte: runs, which Z_RLE finds at a fraction of the time
        png_set_compression_strategy(png, Z_RLE);
      break;
    case PngContent::kLibpngDefault:
      png_set_compression_level(png, 6);
      break;
  }
  png_write_info(png, info);
  if (depth == 16)
    png_set_swap(png);  // our samples are little-endian in memory; PNG is big
  for (int r = 0; r < height; ++r)
    png_write_row(png, const_cast<png_bytep>(rows + static_cast<std::size_t>(r) * row_bytes));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return std::move(ctx.out);
}

void checkSize(int width, int height, std::size_t have, std::size_t per_pixel) {
  if (width <= 0 || height <= 0 ||
      have != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * per_pixel)
    throw RuntimeError(
        fmt::format("png: {} samples do not make a {} x {} image", have, width, height));
}

}  // namespace

std::string encodePngGray16(int width, int height, std::span<const std::uint16_t> pixels,
                            PngContent content) {
  checkSize(width, height, pixels.size(), 1);
  return encode(width, height, PNG_COLOR_TYPE_GRAY, 16,
                reinterpret_cast<const std::uint8_t*>(pixels.data()),
                static_cast<std::size_t>(width) * 2, content);
}
std::string encodePngGray8(int width, int height, std::span<const std::uint8_t> pixels,
                           PngContent content) {
  checkSize(width, height, pixels.size(), 1);
  return encode(width, height, PNG_COLOR_TYPE_GRAY, 8, pixels.data(),
                static_cast<std::size_t>(width), content);
}
std::string encodePngRgb8(int width, int height, std::span<const std::uint8_t> rgb,
                          PngContent content) {
  checkSize(width, height, rgb.size(), 3);
  return encode(width, height, PNG_COLOR_TYPE_RGB, 8, rgb.data(),
                static_cast<std::size_t>(width) * 3, content);
}

PngImage decodePng(std::string_view bytes) {
  struct Reader {
    std::string_view bytes;
    std::size_t at = 0;
  } reader{bytes};
  PngContext ctx;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &ctx, onError, onWarning);
  if (!png)
    throw RuntimeError("png: cannot create the decoder");
  png_infop info = png_create_info_struct(png);
  PngImage out;
  std::vector<std::uint8_t> buffer;
  // NOLINTNEXTLINE(cert-err52-cpp): libpng's error protocol
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw RuntimeError(fmt::format("png: {}", ctx.error.empty() ? "decoding failed" : ctx.error));
  }
  png_set_read_fn(png, &reader, [](png_structp p, png_bytep data, png_size_t length) {
    auto* r = static_cast<Reader*>(png_get_io_ptr(p));
    if (r->bytes.size() - r->at < length)
      png_error(p, "truncated file");
    std::memcpy(data, r->bytes.data() + r->at, length);
    r->at += length;
  });
  png_read_info(png, info);
  const int color = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  if ((color != PNG_COLOR_TYPE_GRAY && color != PNG_COLOR_TYPE_RGB) || (depth != 8 && depth != 16))
    png_error(png, "only 8- and 16-bit grey or RGB images are read");
  if (depth == 16)
    png_set_swap(png);
  png_read_update_info(png, info);
  out.width = static_cast<int>(png_get_image_width(png, info));
  out.height = static_cast<int>(png_get_image_height(png, info));
  out.channels = color == PNG_COLOR_TYPE_RGB ? 3 : 1;
  out.depth = depth;
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  buffer.resize(row_bytes * static_cast<std::size_t>(out.height));
  for (int r = 0; r < out.height; ++r)
    png_read_row(png, buffer.data() + static_cast<std::size_t>(r) * row_bytes, nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  if (depth == 16)
    out.samples16.assign(reinterpret_cast<const std::uint16_t*>(buffer.data()), buffer.size() / 2);
  else
    out.samples8.assign(reinterpret_cast<const char*>(buffer.data()), buffer.size());
  return out;
}

}  // namespace trainsim::io
