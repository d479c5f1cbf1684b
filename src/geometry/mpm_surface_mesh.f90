!> Triangle meshes of surfaces (terrain, closed surfaces of bodies) and their geometric checks.
!>
!> `stl_mesh_type` is what `mpm_stl` reads from an STL file. `check_closed` tells whether a
!> mesh is the closed, consistently oriented surface of a body, and `enclosed_volume` the
!> volume such a surface encloses (its sign: which side the normals point to).
module mpm_surface_mesh
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_strings, only: vector_text => reals_text, i8_text => int_text
    implicit none
    private
    public :: stl_mesh_type, check_closed, enclosed_volume

    !> A triangle mesh read from an STL file.
    type :: stl_mesh_type
        integer :: n = 0
            !! triangles kept (the degenerate ones are skipped)
        real(wp), allocatable :: vertex(:, :, :)
            !! corners (coordinate, corner 1..3, triangle), after scale and offset [m]
        real(wp), allocatable :: normal(:, :)
            !! unit normal (coordinate, triangle), (v2 - v1) x (v3 - v1) normalised: the corners
            !! turn counter-clockwise seen from where the normal points [-]
        real(wp), allocatable :: area(:)
            !! area of each triangle [m2]
        integer, allocatable :: source(:)
            !! number of each triangle in the file (1-based; differs from its position in the
            !! mesh once a degenerate triangle was skipped), for messages
        real(wp) :: lo(3) = 0.0_wp
            !! lower corner of the bounding box of the triangles kept [m]
        real(wp) :: hi(3) = 0.0_wp
            !! upper corner of the bounding box of the triangles kept [m]
        integer :: skipped = 0
            !! degenerate triangles (zero area to round-off) found in the file and skipped
        logical :: binary = .false.
            !! the file was a binary STL (else ASCII)
    end type stl_mesh_type

    ! check_closed numbers corners 1..3n and uses tables of up to 4 x 3n slots, default
    ! integers: n <= (2**31 - 1)/12
    integer, parameter :: max_closed_triangles = 178956970
    ! Low 32 bits (hash of check_closed)
    integer(i8), parameter :: mask32 = 4294967295_i8

contains

    !> Whether a mesh is a closed, consistently oriented surface: corners merged by exact
    !> equality of their coordinates, every edge belongs to exactly two triangles that traverse
    !> it in opposite directions. Self-intersections, several shells and the side the normals
    !> point to (see enclosed_volume) are not checked. Hash tables: O(n) expected time, at most
    !> about 170 bytes per triangle on top of the mesh.
    subroutine check_closed(mesh, closed, message, error)
        type(stl_mesh_type), intent(in) :: mesh
            !! mesh read by read_stl
        logical, intent(out) :: closed
            !! true when the surface is closed and consistently oriented
        character(len=:), allocatable, intent(out) :: message
            !! why not (the first offending edge in triangle order, its triangles by their number
            !! in the file, how many edges have that problem), or a short confirmation
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_other) when out of memory or the mesh is too large to index

        integer, allocatable :: id(:), table(:), uses(:)
        logical, allocatable :: same_direction(:)
        integer :: ncorner, nvertex, nedge, nslot, c, e, s, stat
        integer :: nopen, nshared, nflipped, first_open, first_shared, first_flipped
        character(len=256) :: alloc_message

        closed = .false.
        if (mesh%n == 0) then
            message = "the mesh has no triangles"
            return
        end if
        ! corners and directed edges are numbered 3 (t - 1) + k
        if (mesh%n > max_closed_triangles) then
            call fatal_error(error, "cannot check a surface of "//i8_text(int(mesh%n, i8))// &
                " triangles: at most "//i8_text(int(max_closed_triangles, i8))// &
                " are supported", exit_other)
            return
        end if
        ncorner = 3*mesh%n
        ! power of two, load factor at most 1/2
        nslot = 1
        do while (nslot < 2*ncorner)
            nslot = 2*nslot
        end do
        allocate (id(ncorner), table(nslot), stat=stat, errmsg=alloc_message)
        if (stat /= 0) then
            call out_of_memory()
            return
        end if

        ! Merge corners: equal coordinates, one vertex number.
        table = 0
        nvertex = 0
        do c = 1, ncorner
            s = int(iand(corner_hash(c), int(nslot - 1, i8))) + 1
            do
                if (table(s) == 0) then
                    table(s) = c
                    nvertex = nvertex + 1
                    id(c) = nvertex
                    exit
                else if (all(xyz(table(s)) == xyz(c))) then
                    id(c) = id(table(s))
                    exit
                end if
                s = iand(s, nslot - 1) + 1
            end do
        end do

        ! Undirected edges: table(s) is the first directed edge that uses one, uses(s) how many
        ! do, same_direction(s) whether two of them traverse it the same way.
        deallocate (table)
        allocate (table(nslot), uses(nslot), same_direction(nslot), stat=stat, &
            errmsg=alloc_message)
        if (stat /= 0) then
            call out_of_memory()
            return
        end if
        table = 0
        uses = 0
        same_direction = .false.
        nedge = 0
        do e = 1, ncorner
            s = edge_slot(e)
            if (table(s) == 0) then
                table(s) = e
                nedge = nedge + 1
            else if (id(e) == id(table(s))) then
                same_direction(s) = .true.
            end if
            uses(s) = uses(s) + 1
        end do

        ! Classify each undirected edge once, at its first use, in triangle order.
        nopen = 0
        nshared = 0
        nflipped = 0
        first_open = 0
        first_shared = 0
        first_flipped = 0
        do e = 1, ncorner
            s = edge_slot(e)
            if (table(s) /= e) cycle
            if (uses(s) == 1) then
                nopen = nopen + 1
                if (first_open == 0) first_open = e
            else if (uses(s) > 2) then
                nshared = nshared + 1
                if (first_shared == 0) first_shared = e
            else if (same_direction(s)) then
                nflipped = nflipped + 1
                if (first_flipped == 0) first_flipped = e
            end if
        end do

        closed = nopen + nshared + nflipped == 0
        if (closed) then
            message = "closed and consistently oriented: "//i8_text(int(mesh%n, i8))// &
                " triangles, "//i8_text(int(nedge, i8))//" edges each shared by two "// &
                "triangles in opposite directions"
        else if (nopen > 0) then
            message = edge_text(first_open)//" belongs to 1 triangle (triangle "// &
                triangles_of(first_open)//" of the file): the surface is open"// &
                how_many(nopen, "edge belongs", "edges belong")//" to one triangle only)"
        else if (nshared > 0) then
            s = edge_slot(first_shared)
            message = edge_text(first_shared)//" is shared by "//i8_text(int(uses(s), i8))// &
                " triangles (triangles "//triangles_of(first_shared)//" of the file): the "// &
                "surface is not a manifold"//how_many(nshared, "edge is", "edges are")// &
                " shared by more than two triangles)"
        else
            message = edge_text(first_flipped)//" is traversed in the same direction by "// &
                "triangles "//triangles_of(first_flipped)//" of the file: the surface is "// &
                "inconsistently oriented, one of them is flipped"// &
                how_many(nflipped, "edge has", "edges have")//" this problem)"
        end if

    contains

        !> Coordinates of corner c [m].
        pure function xyz(c) result(x)
            integer, intent(in) :: c
                !! corner number, 3 (t - 1) + k
            real(wp) :: x(3)
                !! its coordinates [m]

            x = mesh%vertex(:, c - 3*((c - 1)/3), (c - 1)/3 + 1)
        end function xyz

        !> The corner after corner c in its triangle (3 -> 1): the end of directed edge c.
        pure integer function next_corner(c)
            integer, intent(in) :: c
                !! corner number, 3 (t - 1) + k

            next_corner = c + 1
            if (mod(c, 3) == 0) next_corner = c - 2
        end function next_corner

        !> Hash of the coordinates of corner c (equal coordinates, equal hash: -0 counts as 0).
        pure integer(i8) function corner_hash(c) result(h)
            integer, intent(in) :: c
                !! corner number, 3 (t - 1) + k

            real(wp) :: x(3)
            integer(i8) :: bits
            integer :: axis

            x = xyz(c)
            h = 0
            do axis = 1, 3
                bits = 0
                if (x(axis) /= 0.0_wp) bits = transfer(x(axis), bits)
                h = mix(h, iand(bits, mask32))
                h = mix(h, iand(ishft(bits, -32), mask32))
            end do
        end function corner_hash

        !> Slot of the undirected edge of directed edge e, inserted or found by its vertices.
        integer function edge_slot(e) result(s)
            integer, intent(in) :: e
                !! directed edge number: from corner e to corner next_corner(e)

            integer :: a, b

            a = min(id(e), id(next_corner(e)))
            b = max(id(e), id(next_corner(e)))
            s = int(iand(mix(mix(0_i8, int(a, i8)), int(b, i8)), int(nslot - 1, i8))) + 1
            do
                if (table(s) == 0) return
                if (min(id(table(s)), id(next_corner(table(s)))) == a .and. &
                    max(id(table(s)), id(next_corner(table(s)))) == b) return
                s = iand(s, nslot - 1) + 1
            end do
        end function edge_slot

        !> "edge from (x, y, z) to (x, y, z)" in the direction the triangle of edge e goes.
        function edge_text(e) result(text)
            integer, intent(in) :: e
                !! directed edge number
            character(len=:), allocatable :: text
                !! the edge for a message

            text = "edge from "//vector_text(xyz(e))//" to "//vector_text(xyz(next_corner(e)))
        end function edge_text

        !> File numbers of the triangles that use the undirected edge of e: "3", "3 and 7".
        function triangles_of(e) result(text)
            integer, intent(in) :: e
                !! the first directed edge that uses the undirected edge
            character(len=:), allocatable :: text
                !! the numbers in the file of the triangles that use it

            integer :: other, s, count, found

            s = edge_slot(e)
            count = uses(s)
            text = ""
            found = 0
            do other = e, ncorner
                if (edge_slot(other) /= s) cycle
                found = found + 1
                if (found > 1 .and. found == count) then
                    text = text//" and "
                else if (found > 1) then
                    text = text//", "
                end if
                text = text//i8_text(int(mesh%source((other - 1)/3 + 1), i8))
                if (found == count) exit
            end do
        end function triangles_of

        !> " (1 edge belongs" or " (3 edges belong".
        function how_many(count, one, several) result(text)
            integer, intent(in) :: count
                !! edges with the problem
            character(len=*), intent(in) :: one
                !! "edge ..." for one of them
            character(len=*), intent(in) :: several
                !! "edges ..." for several
            character(len=:), allocatable :: text
                !! the count in words, an open parenthesis first

            if (count == 1) then
                text = " (1 "//one
            else
                text = " ("//i8_text(int(count, i8))//" "//several
            end if
        end function how_many

        subroutine out_of_memory()
            call fatal_error(error, "out of memory checking a surface of "// &
                i8_text(int(mesh%n, i8))//" triangles: "//trim(alloc_message), exit_other)
        end subroutine out_of_memory

    end subroutine check_closed

    !> Volume enclosed by a closed surface (divergence theorem): positive when the normals point
    !> outwards, negative when the surface is inside out. Meaningful only for a closed mesh.
    pure function enclosed_volume(mesh) result(volume)
        type(stl_mesh_type), intent(in) :: mesh
            !! closed mesh (see check_closed)
        real(wp) :: volume
            !! signed enclosed volume [m3]

        real(wp) :: centre(3), a(3), b(3), c(3)
        integer :: t

        ! relative to the box centre: no cancellation for a body far from the origin
        centre = 0.5_wp*(mesh%lo + mesh%hi)
        volume = 0.0_wp
        do t = 1, mesh%n
            a = mesh%vertex(:, 1, t) - centre
            b = mesh%vertex(:, 2, t) - centre
            c = mesh%vertex(:, 3, t) - centre
            volume = volume + a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) &
                + a(3)*(b(1)*c(2) - b(2)*c(1))
        end do
        volume = volume/6.0_wp
    end function enclosed_volume

    !> One step of a multiplicative hash (after MurmurHash2) on values below 2**32; every
    !> intermediate stays below 2**63, so no integer overflows.
    pure integer(i8) function mix(h, value)
        integer(i8), intent(in) :: h
            !! hash so far, 0 <= h < 2**32
        integer(i8), intent(in) :: value
            !! next value, 0 <= value < 2**32

        integer(i8) :: product

        product = ieor(h, value)*1540483477_i8
        mix = iand(ieor(product, ishft(product, -29)), mask32)
    end function mix

end module mpm_surface_mesh
