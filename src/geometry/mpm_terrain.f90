!> A rigid terrain surface (triangles, e.g. from an STL file) and the distance to it.
!>
!> The triangles are oriented so that their normals point to the side of the material (up:
!> against gravity, decided by the area-weighted mean normal) and indexed by the cells of a
!> regular box (the grid's cells): a cell lists every triangle whose bounding box, grown by
!> `reach`, overlaps the cell. A point then finds every triangle within `reach` of it in its
!> own cell's list, so the distance query is exact up to `reach` and costs only the triangles
!> near the point: a run pays for the terrain where the material is close to it. In 2D the
!> terrain is the section of the surface by the plane z = 0.
module mpm_terrain
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other
    implicit none
    private
    public :: terrain_type, new_terrain, terrain_distance, closest_point_on_triangle, &
        terrain_misses_domain

    character(len=*), parameter :: terrain_misses_domain = "the terrain surface does not "// &
        "come within reach of the domain: no triangle is nearer than one cell to it (check "// &
        "the units, contact.scale and contact.offset)"
        !! refusal of a surface that misses the grid (by new_terrain, or over the images)

    !> The surface and its cell index.
    type :: terrain_type
        integer :: n = 0
            !! triangles
        real(wp), allocatable :: corner(:, :, :)
            !! (3 coordinates, 3 corners, n) [m]
        real(wp), allocatable :: normal(:, :)
            !! unit normal of each triangle, towards the material (3, n)
        real(wp), allocatable :: centre(:, :)
            !! centre of each triangle's bounding sphere (the mean of its corners) (3, n) [m]
        real(wp), allocatable :: radius(:)
            !! radius of each triangle's bounding sphere about `centre` (n) [m]
        real(wp) :: origin(3) = 0.0_wp
            !! corner of the index box [m]
        real(wp) :: h = 1.0_wp
            !! cell size of the index [m]
        integer :: ncells(3) = 1
            !! cells of the index per axis
        real(wp) :: reach = 0.0_wp
            !! distance up to which queries are exact [m]
        integer, allocatable :: first(:)
            !! (cells + 1) start of each cell's triangles in `list` (CSR)
        integer, allocatable :: list(:)
            !! triangles of the cells, cell after cell, each cell's nearest first
        real(wp), allocatable :: list_distance(:)
            !! distance from the cell's centre to the centre of each triangle of `list`
            !! (ascending within a cell) [m]
        real(wp), allocatable :: cell_radius(:)
            !! largest bounding-sphere radius of the triangles of each cell [m]
    end type terrain_type

contains

    !> Orient and index a surface over a box of cells.
    subroutine new_terrain(terrain, corner, origin, ncells, h, dim, reach, gravity, error, &
        allow_empty)
        type(terrain_type), intent(out) :: terrain
            !! the terrain
        real(wp), intent(in) :: corner(:, :, :)
            !! (3, 3, n) triangle corners [m]
        real(wp), intent(in) :: origin(3)
            !! corner of the box (the grid's origin) [m]
        integer, intent(in) :: ncells(3)
            !! cells of the box per axis (the grid's; 1 in z in 2D)
        real(wp), intent(in) :: h
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions: in 2D the box spans z in [-h/2, h/2]
        real(wp), intent(in) :: reach
            !! queries are exact up to this distance [m]
        real(wp), intent(in) :: gravity(3)
            !! gravity: the normals point against it (no change when it is zero) [m/s2]
        type(error_type), allocatable, intent(out) :: error
            !! set when the surface misses the box or memory cannot be allocated
        logical, intent(in), optional :: allow_empty
            !! a surface that misses the box is no error (the box of one image's slab: the
            !! caller decides over the images); the index is then empty

        integer :: t, k, lo(3), hi(3), i, j, m, ncell, stat
        integer, allocatable :: count(:)
        real(wp) :: mean(3), e1(3), e2(3), cross(3), length
        logical :: inside
        character(len=256) :: msg

        terrain%n = size(corner, 3)
        terrain%corner = corner
        allocate (terrain%normal(3, terrain%n), terrain%centre(3, terrain%n), &
            terrain%radius(terrain%n))
        mean = 0.0_wp
        do t = 1, terrain%n
            terrain%centre(:, t) = (corner(:, 1, t) + corner(:, 2, t) + corner(:, 3, t))/3.0_wp
            terrain%radius(t) = max(norm2(corner(:, 1, t) - terrain%centre(:, t)), &
                norm2(corner(:, 2, t) - terrain%centre(:, t)), &
                norm2(corner(:, 3, t) - terrain%centre(:, t)))
            e1 = corner(:, 2, t) - corner(:, 1, t)
            e2 = corner(:, 3, t) - corner(:, 1, t)
            cross = [e1(2)*e2(3) - e1(3)*e2(2), e1(3)*e2(1) - e1(1)*e2(3), &
                e1(1)*e2(2) - e1(2)*e2(1)]
            length = norm2(cross)
            terrain%normal(:, t) = 0.0_wp
            if (length > 0.0_wp) terrain%normal(:, t) = cross/length
            mean = mean + 0.5_wp*cross
        end do
        ! the material side: against gravity
        if (dot_product(mean, gravity) > 0.0_wp) then
            terrain%normal = -terrain%normal
            terrain%corner(:, 2, :) = corner(:, 3, :)
            terrain%corner(:, 3, :) = corner(:, 2, :)
        end if
        terrain%origin = origin
        terrain%ncells = ncells
        if (dim == 2) then
            terrain%origin(3) = -0.5_wp*h
            terrain%ncells(3) = 1
        end if
        terrain%h = h
        terrain%reach = reach
        ncell = product(terrain%ncells)
        allocate (count(ncell), terrain%first(ncell + 1), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the terrain index: "//trim(msg), exit_other)
            return
        end if
        ! two passes over the triangles: count per cell, then fill
        count = 0
        do t = 1, terrain%n
            call cell_range(terrain, t, lo, hi, inside)
            if (.not. inside) cycle
            do k = lo(3), hi(3)
                do j = lo(2), hi(2)
                    do i = lo(1), hi(1)
                        m = cell_index(terrain, [i, j, k])
                        count(m) = count(m) + 1
                    end do
                end do
            end do
        end do
        if (sum(int(count, 8)) == 0 .and. .not. optional_true(allow_empty)) then
            call fatal_error(error, terrain_misses_domain, exit_input)
            return
        end if
        terrain%first(1) = 1
        do m = 1, ncell
            terrain%first(m + 1) = terrain%first(m) + count(m)
        end do
        allocate (terrain%list(terrain%first(ncell + 1) - 1), &
            terrain%list_distance(terrain%first(ncell + 1) - 1), terrain%cell_radius(ncell), &
            stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the terrain index: "//trim(msg), exit_other)
            return
        end if
        count = 0
        do t = 1, terrain%n
            call cell_range(terrain, t, lo, hi, inside)
            if (.not. inside) cycle
            do k = lo(3), hi(3)
                do j = lo(2), hi(2)
                    do i = lo(1), hi(1)
                        m = cell_index(terrain, [i, j, k])
                        terrain%list(terrain%first(m) + count(m)) = t
                        count(m) = count(m) + 1
                    end do
                end do
            end do
        end do
        ! nearest first: a query then finds a close triangle early and stops at the first
        ! triangle that cannot be nearer
        do m = 1, ncell
            call sort_by_distance(terrain, m)
            terrain%cell_radius(m) = 0.0_wp
            do k = terrain%first(m), terrain%first(m + 1) - 1
                terrain%cell_radius(m) = max(terrain%cell_radius(m), &
                    terrain%radius(terrain%list(k)))
            end do
        end do
    end subroutine new_terrain

    !> Order the triangles of cell m by the distance of their centres from the cell's centre
    !> (then by index), with a heap sort (a fine surface lists many triangles per cell).
    subroutine sort_by_distance(terrain, m)
        type(terrain_type), intent(inout) :: terrain
            !! the terrain, its list filled
        integer, intent(in) :: m
            !! cell

        integer :: lo, n, i, ijk(3), rest
        real(wp) :: middle(3)
        real(wp), allocatable :: key(:)
        integer, allocatable :: item(:)

        lo = terrain%first(m)
        n = terrain%first(m + 1) - lo
        if (n < 1) return
        ijk(1) = mod(m - 1, terrain%ncells(1))
        ijk(2) = mod((m - 1)/terrain%ncells(1), terrain%ncells(2))
        ijk(3) = (m - 1)/(terrain%ncells(1)*terrain%ncells(2))
        middle = terrain%origin + (real(ijk, wp) + 0.5_wp)*terrain%h
        item = terrain%list(lo:lo + n - 1)
        allocate (key(n))
        do i = 1, n
            key(i) = sum((terrain%centre(:, item(i)) - middle)**2)
        end do
        ! heap sort: build a max-heap, then move the largest to the end
        do i = n/2, 1, -1
            call sift(i, n)
        end do
        do rest = n, 2, -1
            call swap(1, rest)
            call sift(1, rest - 1)
        end do
        terrain%list(lo:lo + n - 1) = item
        terrain%list_distance(lo:lo + n - 1) = sqrt(key)

    contains

        logical function after(a, b)
            integer, intent(in) :: a, b
            after = key(a) > key(b) .or. (key(a) == key(b) .and. item(a) > item(b))
        end function after

        subroutine swap(a, b)
            integer, intent(in) :: a, b
            real(wp) :: k
            integer :: j
            k = key(a)
            key(a) = key(b)
            key(b) = k
            j = item(a)
            item(a) = item(b)
            item(b) = j
        end subroutine swap

        subroutine sift(start, last)
            integer, intent(in) :: start, last
            integer :: root, child
            root = start
            do while (2*root <= last)
                child = 2*root
                if (child < last) then
                    if (after(child + 1, child)) child = child + 1
                end if
                if (.not. after(child, root)) return
                call swap(root, child)
                root = child
            end do
        end subroutine sift

    end subroutine sort_by_distance

    !> Cells (0-based, clamped to the box) that the bounding box of triangle t, grown by
    !> reach, overlaps; `inside` is false when it misses the box.
    pure subroutine cell_range(terrain, t, lo, hi, inside)
        type(terrain_type), intent(in) :: terrain
        integer, intent(in) :: t
        integer, intent(out) :: lo(3), hi(3)
        logical, intent(out) :: inside

        integer :: a
        real(wp) :: low, high

        inside = .false.
        lo = 0
        hi = -1
        if (all(terrain%normal(:, t) == 0.0_wp)) return   ! degenerate: no face to touch
        do a = 1, 3
            low = (minval(terrain%corner(a, :, t)) - terrain%reach - terrain%origin(a))/terrain%h
            high = (maxval(terrain%corner(a, :, t)) + terrain%reach - terrain%origin(a))/terrain%h
            if (high < 0.0_wp .or. low > real(terrain%ncells(a), wp)) return
            lo(a) = max(0, floor(low))
            hi(a) = min(terrain%ncells(a) - 1, floor(high))
        end do
        inside = .true.
    end subroutine cell_range

    pure logical function optional_true(flag)
        logical, intent(in), optional :: flag
        optional_true = .false.
        if (present(flag)) optional_true = flag
    end function optional_true

    pure integer function cell_index(terrain, ijk)
        type(terrain_type), intent(in) :: terrain
        integer, intent(in) :: ijk(3)
        cell_index = 1 + ijk(1) + terrain%ncells(1)*(ijk(2) + terrain%ncells(2)*ijk(3))
    end function cell_index

    !> Signed distance from x to the surface (positive on the material's side) and the normal
    !> of the nearest triangle (towards the material); found is false when no triangle is
    !> within reach (or x is outside the index box).
    pure subroutine terrain_distance(terrain, x, found, d, n)
        type(terrain_type), intent(in) :: terrain
            !! the terrain
        real(wp), intent(in) :: x(3)
            !! point (z = 0 in 2D) [m]
        logical, intent(out) :: found
            !! a triangle is within reach
        real(wp), intent(out) :: d
            !! signed distance [m] (when found)
        real(wp), intent(out) :: n(3)
            !! normal of the nearest triangle, towards the material (when found)

        integer :: ijk(3), a, m, q, t, nearest
        real(wp) :: p(3), dist, best, bound, off, lower, v(3), h, rho, limit
        real(wp), parameter :: slack = 1.0e-9_wp
            !! relative margin of the sphere test against rounding [-]

        found = .false.
        d = huge(1.0_wp)
        n = 0.0_wp
        do a = 1, 3
            ijk(a) = floor((x(a) - terrain%origin(a))/terrain%h)
            if (ijk(a) < 0 .or. ijk(a) >= terrain%ncells(a)) return
        end do
        m = cell_index(terrain, ijk)
        best = huge(1.0_wp)
        nearest = huge(1)
        ! distance from x to the cell's centre: a triangle of the cell whose centre is at c
        ! from the cell's centre is at least c - off - cell_radius from x
        off = norm2(x - (terrain%origin + (real(ijk, wp) + 0.5_wp)*terrain%h))
        do q = terrain%first(m), terrain%first(m + 1) - 1
            t = terrain%list(q)
            ! only a triangle within reach counts, and then only one as near as the nearest
            ! so far: a triangle that cannot be nearer than `limit` is no candidate
            limit = min(best, terrain%reach)
            ! the list is ordered by c: once the bound of the list's order is beyond the
            ! limit, no later triangle is a candidate
            lower = terrain%list_distance(q) - off - terrain%cell_radius(m)
            if (lower > limit + slack*(terrain%list_distance(q) + off + &
                terrain%cell_radius(m) + limit)) exit
            ! the triangle lies in its plane within radius r of its centre c: its distance
            ! from x is at least sqrt(h^2 + max(0, rho - r)^2), h the height of x over the
            ! plane and rho the distance of x's foot on the plane from c
            v = x - terrain%centre(:, t)
            h = dot_product(v, terrain%normal(:, t))
            rho = sqrt(max(0.0_wp, sum(v*v) - h*h))
            bound = limit + slack*(rho + abs(h) + terrain%radius(t) + limit)
            if (h*h + max(0.0_wp, rho - terrain%radius(t))**2 > bound*bound) cycle
            p = closest_point_on_triangle(x, terrain%corner(:, 1, t), terrain%corner(:, 2, t), &
                terrain%corner(:, 3, t))
            dist = norm2(x - p)
            ! at equal distances (a point over a shared edge) the lowest index wins, whatever
            ! the order of the list
            if (dist < best .or. (dist == best .and. t < nearest)) then
                best = dist
                nearest = t
                n = terrain%normal(:, t)
                d = sign(dist, dot_product(x - p, n))
            end if
        end do
        found = best <= terrain%reach
    end subroutine terrain_distance

    !> The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection,
    !> 5.1.5: the Voronoi regions of the corners, edges and face).
    pure function closest_point_on_triangle(p, a, b, c) result(q)
        real(wp), intent(in) :: p(3)
            !! point
        real(wp), intent(in) :: a(3), b(3), c(3)
            !! corners
        real(wp) :: q(3)

        real(wp) :: ab(3), ac(3), ap(3), bp(3), cp(3), d1, d2, d3, d4, d5, d6, va, vb, vc, &
            v, w, denom

        ab = b - a
        ac = c - a
        ap = p - a
        d1 = dot_product(ab, ap)
        d2 = dot_product(ac, ap)
        if (d1 <= 0.0_wp .and. d2 <= 0.0_wp) then
            q = a
            return
        end if
        bp = p - b
        d3 = dot_product(ab, bp)
        d4 = dot_product(ac, bp)
        if (d3 >= 0.0_wp .and. d4 <= d3) then
            q = b
            return
        end if
        vc = d1*d4 - d3*d2
        if (vc <= 0.0_wp .and. d1 >= 0.0_wp .and. d3 <= 0.0_wp) then
            q = a + (d1/(d1 - d3))*ab
            return
        end if
        cp = p - c
        d5 = dot_product(ab, cp)
        d6 = dot_product(ac, cp)
        if (d6 >= 0.0_wp .and. d5 <= d6) then
            q = c
            return
        end if
        vb = d5*d2 - d1*d6
        if (vb <= 0.0_wp .and. d2 >= 0.0_wp .and. d6 <= 0.0_wp) then
            q = a + (d2/(d2 - d6))*ac
            return
        end if
        va = d3*d6 - d5*d4
        if (va <= 0.0_wp .and. (d4 - d3) >= 0.0_wp .and. (d5 - d6) >= 0.0_wp) then
            q = b + ((d4 - d3)/((d4 - d3) + (d5 - d6)))*(c - b)
            return
        end if
        denom = 1.0_wp/(va + vb + vc)
        v = vb*denom
        w = vc*denom
        q = a + ab*v + ac*w
    end function closest_point_on_triangle

end module mpm_terrain
