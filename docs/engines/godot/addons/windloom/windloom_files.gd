class_name WindloomFiles
extends RefCounted
## The files of a bake as WindloomField reads them, each decoded to its stored samples
## (`[channels a cell, PackedFloat32Array]`) or a String saying in one line what is wrong:
## an image Godot decoded, an imported `.ctex` an export carries, a DDS volume, and a PNG at
## all of its 16 bits (Godot's own PNG loader keeps 8). Each checks the cells the manifest
## says the file holds before it reads the texels.

## An image's texels as RGBA floats: [4, PackedFloat32Array], checked to hold `cells` texels.
static func image_samples(image: Image, cells: int) -> Variant:
	if image.is_compressed():
		return "a VRAM-compressed texture: import it Lossless (the manifest's engines.godot.import)"
	if image.get_width() * image.get_height() != cells:
		return "%d × %d texels, where the manifest says %d cells" % [image.get_width(), image.get_height(), cells]
	image.clear_mipmaps()
	image.convert(Image.FORMAT_RGBAF)
	return [4, image.get_data().to_float32_array()]


## An image an export carries only as imported: its `.ctex`, found through its `.import`
## file's remap, read without the GPU (a float texture keeps its floats; Godot imports a
## float image Lossless as raw texels, a PNG as PNG data at 8 bits a channel).
static func imported(path: String, cells: int) -> Variant:
	var cfg := ConfigFile.new()
	if cfg.load(path + ".import") != OK:
		return "%s.import cannot be read" % path
	var target := str(cfg.get_value("remap", "path", ""))
	if target.is_empty():
		for key in cfg.get_section_keys("remap") if cfg.has_section("remap") else []:
			if key.begins_with("path."):
				target = str(cfg.get_value("remap", key))
				break
	if not target.begins_with("res://"):
		return "%s.import names no imported texture" % path
	var f := FileAccess.open(target, FileAccess.READ)
	if f == null:
		return "%s (imported) cannot be opened (import the bake in the editor before exporting)" % target
	var header := f.get_buffer(52)
	if header.size() < 52 or header.slice(0, 4).get_string_from_ascii() != "GST2":
		return "%s is not a CompressedTexture2D" % target
	# "GST2", then version, width, height, flags, mipmap limit and three reserved (u32 each);
	# then the image: data format (u32), width, height (u16), mipmaps, image format (u32).
	var data_format := header.decode_u32(36)
	var w := header.decode_u16(40)
	var h := header.decode_u16(42)
	var image_format := header.decode_u32(48)
	if w * h != cells:
		return "%s: %d × %d texels, where the manifest says %d cells" % [target, w, h, cells]
	var image: Image
	if data_format == 0:  # raw texels
		if image_format >= Image.FORMAT_DXT1:
			return "%s: VRAM-compressed (image format %d): import it Lossless" % [target, image_format]
		var size := Image.create_empty(1, 1, false, image_format).get_data().size() * w * h
		if f.get_length() < 52 + size:
			return "%s is shorter than its %d × %d texels" % [target, w, h]
		image = Image.create_from_data(w, h, false, image_format, f.get_buffer(size))
	elif data_format == 1 or data_format == 2:  # PNG or WebP data
		var size := f.get_32()
		if size > f.get_length() - 56:
			return "%s is shorter than its image" % target
		image = Image.new()
		var buffer := f.get_buffer(size)
		if (image.load_png_from_buffer(buffer) if data_format == 1 else image.load_webp_from_buffer(buffer)) != OK:
			return "%s: its image cannot be decoded" % target
	else:
		return "%s: VRAM-compressed (data format %d): import it Lossless" % [target, data_format]
	return image_samples(image, cells)


## A DDS volume as windloom writes it (DX10 header, DXGI 2 = RGBA f32, 10 = RGBA f16).
static func dds(data: PackedByteArray, cells: int) -> Variant:
	var head = dds_header(data)
	if head is String:
		return head
	var texels: int = head.width * head.height * maxi(head.depth, 1)
	if texels != cells:
		return "%d texels, where the manifest says %d cells" % [texels, cells]
	var bytes: int = cells * head.texel_bytes
	if data.size() < 148 + bytes:
		return "shorter than its %d texels" % cells
	if head.format == Image.FORMAT_RGBAF:
		return [4, data.slice(148, 148 + bytes).to_float32_array()]
	var out := PackedFloat32Array()
	out.resize(cells * 4)
	for i in cells * 4:
		out[i] = data.decode_half(148 + 2 * i)
	return [4, out]


## What a DDS file's header says of its texels.
class DdsHeader:
	var width: int
	var height: int
	var depth: int
	## Image.FORMAT_RGBAF (DXGI 2) or Image.FORMAT_RGBAH (DXGI 10).
	var format: int
	var texel_bytes: int


## A DDS file's header as windloom writes it (148 bytes: "DDS ", the DX10 extension, DXGI
## format 2 = RGBA f32 or 10 = RGBA f16) as a DdsHeader, or a String saying why it is not
## one. The texels follow at byte 148, row by row, slice by slice.
static func dds_header(header: PackedByteArray) -> Variant:
	if header.size() < 148 or header.slice(0, 4).get_string_from_ascii() != "DDS " or header.slice(84, 88).get_string_from_ascii() != "DX10":
		return "not a DDS file with a DX10 header"
	var dxgi := header.decode_u32(128)
	if dxgi != 2 and dxgi != 10:
		return "DXGI format %d, not 2 (RGBA f32) or 10 (RGBA f16)" % dxgi
	var head := DdsHeader.new()
	head.height = header.decode_u32(12)
	head.width = header.decode_u32(16)
	head.depth = header.decode_u32(24)
	head.format = Image.FORMAT_RGBAF if dxgi == 2 else Image.FORMAT_RGBAH
	head.texel_bytes = 16 if dxgi == 2 else 8
	return head


## A PNG's samples as a GPU samples them (n / 255, or n / 65535 at 16 bits: all 16 kept,
## where Godot's own loader keeps 8), row by row: [channels, PackedFloat32Array], or a
## String. Its header must give `size` pixels before anything is inflated.
static func png_samples(data: PackedByteArray, size: Vector2i) -> Variant:
	if data.size() < 33 or data.slice(0, 8) != PackedByteArray([137, 80, 78, 71, 13, 10, 26, 10]):
		return "not a PNG file"
	var w := _be32(data, 16)
	var h := _be32(data, 20)
	var depth := data[24]
	var colour := data[25]
	if data.slice(12, 16).get_string_from_ascii() != "IHDR" or data[28] != 0:
		return "a PNG that is interlaced or has no header first"
	if w != size.x or h != size.y:
		return "%d × %d pixels, where the manifest says %d × %d" % [w, h, size.x, size.y]
	var channels: int = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour, 0)
	if channels == 0 or not (depth == 8 or depth == 16):
		return "a PNG of colour type %d at %d bits (grey, RGB, grey-alpha or RGBA at 8 or 16 bits)" % [colour, depth]
	var bpp := channels * depth / 8
	var stride := w * bpp
	var compressed := PackedByteArray()
	var at := 8
	while at + 12 <= data.size():
		var length := _be32(data, at)
		var type := data.slice(at + 4, at + 8).get_string_from_ascii()
		if length > data.size() - at - 12:
			return "a PNG chunk runs past the file's end"
		if type == "IDAT":
			compressed.append_array(data.slice(at + 8, at + 8 + length))
		elif type == "IEND":
			break
		at += 12 + length
	var rows := compressed.decompress(h * (stride + 1), FileAccess.COMPRESSION_DEFLATE) if not compressed.is_empty() else PackedByteArray()
	if rows.size() != h * (stride + 1):
		return "its pixels do not inflate to %d × %d" % [w, h]
	# Unfilter (PNG's five filters), row by row, in place in `out`.
	var out := PackedByteArray()
	out.resize(h * stride)
	for j in h:
		var filter := rows[j * (stride + 1)]
		var src := j * (stride + 1) + 1
		var dst := j * stride
		var up := dst - stride
		match filter:
			0:
				for i in stride:
					out[dst + i] = rows[src + i]
			1:
				for i in stride:
					out[dst + i] = (rows[src + i] + (out[dst + i - bpp] if i >= bpp else 0)) & 255
			2:
				for i in stride:
					out[dst + i] = (rows[src + i] + (out[up + i] if j > 0 else 0)) & 255
			3:
				for i in stride:
					var left := out[dst + i - bpp] if i >= bpp else 0
					var above := out[up + i] if j > 0 else 0
					out[dst + i] = (rows[src + i] + ((left + above) >> 1)) & 255
			4:
				for i in stride:
					var a := out[dst + i - bpp] if i >= bpp else 0
					var b := out[up + i] if j > 0 else 0
					var c := out[up + i - bpp] if j > 0 and i >= bpp else 0
					var p := a + b - c
					var pa := absi(p - a)
					var pb := absi(p - b)
					var pc := absi(p - c)
					var pred := a if pa <= pb and pa <= pc else (b if pb <= pc else c)
					out[dst + i] = (rows[src + i] + pred) & 255
			_:
				return "row %d has PNG filter %d (0 to 4)" % [j, filter]
	var samples := PackedFloat32Array()
	if depth == 8:
		samples.resize(out.size())
		for i in out.size():
			samples[i] = out[i] / 255.0
	else:
		samples.resize(out.size() / 2)
		for i in samples.size():
			samples[i] = ((out[2 * i] << 8) | out[2 * i + 1]) / 65535.0
	return [channels, samples]


static func _be32(data: PackedByteArray, at: int) -> int:
	return (data[at] << 24) | (data[at + 1] << 16) | (data[at + 2] << 8) | data[at + 3]
