#include "engine/output/exr_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <algorithm>
#include <exception>
#include <set>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"

namespace cr {
namespace {

// Generous bound that still rejects corrupt headers asking for absurd allocations.
constexpr long long kMaxPixels = 1LL << 28;

void write_channels_to(const std::string& file, int width, int height,
                       const std::vector<ExrChannel>& channels) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer frame;
  // Half channels need their own storage in half precision; kept alive until writePixels.
  std::vector<std::vector<half>> half_storage;
  half_storage.reserve(channels.size());
  for (const ExrChannel& channel : channels) {
    if (channel.type == ExrPixelType::Half) {
      std::vector<half>& values = half_storage.emplace_back(pixels);
      for (size_t i = 0; i < pixels; ++i) values[i] = half(channel.values[i]);
      header.channels().insert(channel.name, Imf::Channel(Imf::HALF));
      frame.insert(channel.name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(values.data()),
                                            sizeof(half), sizeof(half) * width));
    } else {
      header.channels().insert(channel.name, Imf::Channel(Imf::FLOAT));
      frame.insert(channel.name,
                   Imf::Slice(Imf::FLOAT,
                              reinterpret_cast<char*>(const_cast<float*>(channel.values.data())),
                              sizeof(float), sizeof(float) * width));
    }
  }
  Imf::OutputFile out(file.c_str(), header);
  out.setFrameBuffer(frame);
  out.writePixels(height);
}

}  // namespace

void write_exr_channels(const std::string& path, int width, int height,
                        const std::vector<ExrChannel>& channels) {
  if (width <= 0 || height <= 0)
    throw Error(path + ": cannot write EXR of size " + std::to_string(width) + "x" +
                std::to_string(height));
  if (channels.empty()) throw Error(path + ": cannot write EXR without channels");
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  std::set<std::string> names;
  for (const ExrChannel& channel : channels) {
    if (channel.name.empty()) throw Error(path + ": EXR channel with an empty name");
    if (!names.insert(channel.name).second)
      throw Error(path + ": duplicate EXR channel '" + channel.name + "'");
    if (channel.values.size() != pixels)
      throw Error(path + ": EXR channel '" + channel.name + "' has " +
                  std::to_string(channel.values.size()) + " values, expected " +
                  std::to_string(pixels));
  }
  write_file_atomic(path, [&](const std::string& temp) {
    try {
      write_channels_to(temp, width, height, channels);
    } catch (const std::exception& e) {
      throw Error(path + ": cannot write EXR: " + e.what());
    }
  });
}

void write_exr(const std::string& path, const ExrImage& image) {
  const ImageRGBf& color = image.color;
  const size_t pixels = color.pixel_count();
  if (color.rgb.size() != pixels * 3)
    throw Error(path + ": EXR colour data does not match " + std::to_string(color.width) + "x" +
                std::to_string(color.height));
  std::vector<ExrChannel> channels;
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    ExrChannel& channel = channels.emplace_back();
    channel.name = names[c];
    channel.type = ExrPixelType::Half;
    channel.values.resize(pixels);
    for (size_t i = 0; i < pixels; ++i) channel.values[i] = color.rgb[i * 3 + c];
  }
  if (!image.depth.empty()) channels.push_back({"Z", ExrPixelType::Float, image.depth});
  for (const ExrChannel& aov : image.aovs) {
    if (aov.name == "R" || aov.name == "G" || aov.name == "B" || aov.name == "Z")
      throw Error(path + ": AOV name '" + aov.name + "' is reserved");
    channels.push_back(aov);
  }
  write_exr_channels(path, color.width, color.height, channels);
}

ExrImage read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const long long width = static_cast<long long>(window.max.x) - window.min.x + 1;
    const long long height = static_cast<long long>(window.max.y) - window.min.y + 1;
    if (width <= 0 || height <= 0 || width * height > kMaxPixels)
      throw InputError(path, "EXR data window has unsupported size " + std::to_string(width) +
                                 "x" + std::to_string(height));
    const Imf::ChannelList& list = header.channels();
    std::vector<std::string> names;
    for (auto it = list.begin(); it != list.end(); ++it) {
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        throw InputError(path, std::string("EXR channel '") + it.name() +
                                   "' is subsampled, which is not supported");
      names.emplace_back(it.name());
    }
    for (const char* required : {"R", "G", "B"}) {
      if (std::find(names.begin(), names.end(), required) == names.end()) {
        std::string present;
        for (const std::string& name : names) present += (present.empty() ? "" : ", ") + name;
        throw InputError(path, std::string("EXR is missing channel '") + required +
                                   "' (channels present: " +
                                   (present.empty() ? "none" : present) + ")");
      }
    }

    const size_t pixels = static_cast<size_t>(width * height);
    std::vector<std::vector<float>> planes(names.size(), std::vector<float>(pixels));
    Imf::FrameBuffer frame;
    for (size_t i = 0; i < names.size(); ++i) {
      frame.insert(names[i], Imf::Slice::Make(Imf::FLOAT, planes[i].data(), window,
                                              sizeof(float), sizeof(float) * width));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);

    ExrImage image;
    image.color = ImageRGBf(static_cast<int>(width), static_cast<int>(height));
    for (size_t i = 0; i < names.size(); ++i) {
      const std::string& name = names[i];
      if (name == "R" || name == "G" || name == "B") {
        const int c = name == "R" ? 0 : name == "G" ? 1 : 2;
        for (size_t p = 0; p < pixels; ++p) image.color.rgb[p * 3 + c] = planes[i][p];
      } else if (name == "Z") {
        image.depth = std::move(planes[i]);
      } else {
        image.aovs.push_back({name, ExrPixelType::Float, std::move(planes[i])});
      }
    }
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot read EXR: ") + e.what());
  }
}

}  // namespace cr
