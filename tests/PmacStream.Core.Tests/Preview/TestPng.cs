using System.Buffers.Binary;
using System.IO.Compression;
using PmacStream.Preview;

namespace PmacStream.Core.Tests.Preview;

/// <summary>A small PNG reader for 8-bit RGBA non-interlaced files, checking every chunk's CRC.</summary>
internal static class TestPng
{
    public sealed record Decoded(int Width, int Height, byte BitDepth, byte ColourType, byte Interlace, byte[] Pixels, List<string> ChunkTypes)
    {
        public Rgba At(int x, int y)
        {
            var o = ((y * Width) + x) * 4;
            return new Rgba(Pixels[o], Pixels[o + 1], Pixels[o + 2], Pixels[o + 3]);
        }
    }

    public static Decoded Decode(byte[] png)
    {
        png.AsSpan(0, 8).ToArray().Should().Equal(0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A);
        var pos = 8;
        var types = new List<string>();
        using var idat = new MemoryStream();
        int w = 0, h = 0;
        byte depth = 0, colour = 0, interlace = 0;
        while (pos < png.Length)
        {
            var len = BinaryPrimitives.ReadInt32BigEndian(png.AsSpan(pos));
            var type = System.Text.Encoding.ASCII.GetString(png, pos + 4, 4);
            var data = png.AsSpan(pos + 8, len);
            var crc = BinaryPrimitives.ReadUInt32BigEndian(png.AsSpan(pos + 8 + len));
            Crc32.Compute(png.AsSpan(pos + 4, len + 4)).Should().Be(crc, $"the CRC of chunk {type}");
            types.Add(type);
            if (type == "IHDR")
            {
                w = BinaryPrimitives.ReadInt32BigEndian(data);
                h = BinaryPrimitives.ReadInt32BigEndian(data[4..]);
                depth = data[8];
                colour = data[9];
                interlace = data[12];
            }
            else if (type == "IDAT")
            {
                idat.Write(data);
            }

            pos += 12 + len;
        }

        idat.Position = 0;
        using var z = new ZLibStream(idat, CompressionMode.Decompress);
        using var raw = new MemoryStream();
        z.CopyTo(raw);
        var bytes = raw.ToArray();
        var stride = w * 4;
        bytes.Length.Should().Be((stride + 1) * h);
        var pixels = new byte[stride * h];
        for (var y = 0; y < h; y++)
        {
            var filter = bytes[y * (stride + 1)];
            for (var i = 0; i < stride; i++)
            {
                int x = bytes[(y * (stride + 1)) + 1 + i];
                int a = i >= 4 ? pixels[(y * stride) + i - 4] : 0;
                int b = y > 0 ? pixels[((y - 1) * stride) + i] : 0;
                int c = i >= 4 && y > 0 ? pixels[((y - 1) * stride) + i - 4] : 0;
                var v = filter switch
                {
                    0 => x,
                    1 => x + a,
                    2 => x + b,
                    3 => x + ((a + b) / 2),
                    4 => x + Paeth(a, b, c),
                    _ => throw new InvalidDataException($"filter {filter}"),
                };
                pixels[(y * stride) + i] = (byte)v;
            }
        }

        return new Decoded(w, h, depth, colour, interlace, pixels, types);
    }

    private static int Paeth(int a, int b, int c)
    {
        var p = a + b - c;
        var pa = Math.Abs(p - a);
        var pb = Math.Abs(p - b);
        var pc = Math.Abs(p - c);
        return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
    }
}
