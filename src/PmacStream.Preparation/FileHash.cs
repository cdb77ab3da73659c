using System.Security.Cryptography;

namespace PmacStream.Preparation;

/// <summary>The SHA-256 of a file, as manifests and job records keep it (lower-case hex).</summary>
public static class FileHash
{
    /// <summary>Hashes a whole file in one sequential read.</summary>
    public static string Sha256Hex(string path, CancellationToken cancellationToken = default) => Sha256Hex(path, out _, cancellationToken);

    /// <summary>Hashes a whole file in one sequential read and gives its size as read.</summary>
    public static string Sha256Hex(string path, out long size, CancellationToken cancellationToken = default)
    {
        using var s = new FileStream(path, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
        using var sha = IncrementalHash.CreateHash(HashAlgorithmName.SHA256);
        var buffer = new byte[1 << 20];
        size = 0;
        int n;
        while ((n = s.Read(buffer, 0, buffer.Length)) > 0)
        {
            cancellationToken.ThrowIfCancellationRequested();
            sha.AppendData(buffer, 0, n);
            size += n;
        }

        return Convert.ToHexStringLower(sha.GetHashAndReset());
    }

    /// <summary>True when two hex digests name the same bytes (case does not matter).</summary>
    public static bool SameDigest(string? a, string? b) => a is not null && b is not null && string.Equals(a, b, StringComparison.OrdinalIgnoreCase);
}
