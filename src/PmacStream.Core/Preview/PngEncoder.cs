using System.Buffers.Binary;
using System.IO.Compression;

namespace PmacStream.Preview;

/// <summary>
/// Writes <see cref="RgbaImage"/> as a PNG: 8-bit RGBA (colour type 6), one IDAT compressed with zlib, each row
/// with the Up filter (toolpath pictures are mostly background, so Up rows compress to almost nothing).
/// </summary>
public static class PngEncoder
{
    private static readonly byte[] Signature = [0x89, (byte)'P', (byte)'N', (byte)'G', 0x0D, 0x0A, 0x1A, 0x0A];

    /// <summary>The PNG file bytes.</summary>
    public static byte[] Encode(RgbaImage image)
    {
        using var ms = new MemoryStream();
        Write(image, ms);
        return ms.ToArray();
    }

    /// <summary>Writes the PNG to <paramref name="output"/>.</summary>
    public static void Write(RgbaImage image, Stream output)
    {
        output.Write(Signature);
        Span<byte> ihdr = stackalloc byte[13];
        BinaryPrimitives.WriteInt32BigEndian(ihdr, image.Width);
        BinaryPrimitives.WriteInt32BigEndian(ihdr[4..], image.Height);
        ihdr[8] = 8; // bit depth
        ihdr[9] = 6; // RGBA
        ihdr[10] = 0; // deflate
        ihdr[11] = 0; // adaptive filtering
        ihdr[12] = 0; // no interlace
        WriteChunk(output, "IHDR"u8, ihdr);

        using (var idat = new MemoryStream())
        {
            using (var z = new ZLibStream(idat, CompressionLevel.Optimal, leaveOpen: true))
            {
                var stride = image.Width * 4;
                var row = new byte[stride + 1];
                var px = image.Pixels;
                for (var y = 0; y < image.Height; y++)
                {
                    var cur = px.AsSpan(y * stride, stride);
                    if (y == 0)
                    {
                        row[0] = 0; // None
                        cur.CopyTo(row.AsSpan(1));
                    }
                    else
                    {
                        row[0] = 2; // Up
                        var prev = px.AsSpan((y - 1) * stride, stride);
                        for (var i = 0; i < stride; i++)
                        {
                            row[i + 1] = (byte)(cur[i] - prev[i]);
                        }
                    }

                    z.Write(row);
                }
            }

            WriteChunk(output, "IDAT"u8, idat.GetBuffer().AsSpan(0, (int)idat.Length));
        }

        WriteChunk(output, "IEND"u8, ReadOnlySpan<byte>.Empty);
    }

    /// <summary>Writes the PNG to a file atomically (a temporary file renamed into place), so no half picture is left.</summary>
    public static void WriteFile(RgbaImage image, string path)
    {
        var full = Path.GetFullPath(path);
        var temp = full + ".tmp" + Environment.ProcessId.ToString(System.Globalization.CultureInfo.InvariantCulture);
        try
        {
            using (var fs = new FileStream(temp, FileMode.Create, FileAccess.Write, FileShare.None))
            {
                Write(image, fs);
            }

            File.Move(temp, full, overwrite: true);
        }
        finally
        {
            if (File.Exists(temp))
            {
                File.Delete(temp);
            }
        }
    }

    private static void WriteChunk(Stream output, ReadOnlySpan<byte> type, ReadOnlySpan<byte> data)
    {
        Span<byte> head = stackalloc byte[8];
        BinaryPrimitives.WriteInt32BigEndian(head, data.Length);
        type.CopyTo(head[4..]);
        output.Write(head);
        output.Write(data);
        var crc = Crc32.Update(Crc32.Update(Crc32.Initial, type), data) ^ 0xFFFFFFFFu;
        Span<byte> tail = stackalloc byte[4];
        BinaryPrimitives.WriteUInt32BigEndian(tail, crc);
        output.Write(tail);
    }
}

/// <summary>CRC-32 (ISO 3309 / PNG, reflected polynomial 0xEDB88320), table driven.</summary>
public static class Crc32
{
    /// <summary>The register's starting value (the final value is XORed with 0xFFFFFFFF).</summary>
    public const uint Initial = 0xFFFFFFFFu;

    private static readonly uint[] Table = BuildTable();

    /// <summary>Runs <paramref name="data"/> through the register.</summary>
    public static uint Update(uint crc, ReadOnlySpan<byte> data)
    {
        foreach (var b in data)
        {
            crc = Table[(crc ^ b) & 0xFF] ^ (crc >> 8);
        }

        return crc;
    }

    /// <summary>The CRC-32 of <paramref name="data"/>.</summary>
    public static uint Compute(ReadOnlySpan<byte> data) => Update(Initial, data) ^ 0xFFFFFFFFu;

    private static uint[] BuildTable()
    {
        var table = new uint[256];
        for (uint n = 0; n < 256; n++)
        {
            var c = n;
            for (var k = 0; k < 8; k++)
            {
                c = (c & 1) != 0 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            }

            table[n] = c;
        }

        return table;
    }
}
