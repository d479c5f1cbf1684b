!> Simple polygons of the plane (2D bodies): their checks and the closed surface the particle
!> filler takes.
!>
!> A polygon is its vertices in order (either sense), the last joined to the first. It is
!> simple when no two of its edges meet except adjacent ones at their common vertex. The
!> filler of the bodies (mpm_case_sites) counts the crossings of a line along y with a closed
!> surface cut by the plane z = 0; the walls of the polygon extruded across that plane are
!> such a surface (the caps are parallel to the lines and never crossed).
module mpm_polygon
    use mpm_kinds, only: wp
    implicit none
    private
    public :: polygon_area, polygon_crossing, polygon_walls

contains

    !> Signed area of a polygon (positive counter-clockwise), the shoelace sum [m2].
    pure real(wp) function polygon_area(p)
        real(wp), intent(in) :: p(:, :)
            !! vertices (2, n) [m]

        integer :: i, j, n

        n = size(p, 2)
        polygon_area = 0.0_wp
        do i = 1, n
            j = modulo(i, n) + 1
            polygon_area = polygon_area + p(1, i)*p(2, j) - p(1, j)*p(2, i)
        end do
        polygon_area = 0.5_wp*polygon_area
    end function polygon_area

    !> The first two edges of a polygon that meet though they are not neighbours, or
    !> neighbours that overlap along a line or share more than their common vertex; edge i
    !> runs from vertex i to vertex i + 1 (the last to vertex 1). Zero for a simple polygon.
    !> A vertex repeated (an edge of zero length) counts as edges that meet.
    pure subroutine polygon_crossing(p, e1, e2)
        real(wp), intent(in) :: p(:, :)
            !! vertices (2, n) [m]
        integer, intent(out) :: e1, e2
            !! the edges (0 when none)

        integer :: i, j, n

        n = size(p, 2)
        e1 = 0
        e2 = 0
        do i = 1, n
            if (all(p(:, i) == p(:, modulo(i, n) + 1))) then
                e1 = i
                e2 = i
                return
            end if
        end do
        do i = 1, n - 1
            do j = i + 1, n
                if (j == i + 1 .or. (i == 1 .and. j == n)) then
                    ! neighbours: only their common vertex may be shared, so they must not
                    ! fold back onto each other
                    if (folds_back(i, j)) then
                        e1 = i
                        e2 = j
                        return
                    end if
                else if (segments_meet(p(:, i), p(:, modulo(i, n) + 1), p(:, j), &
                    p(:, modulo(j, n) + 1))) then
                    e1 = i
                    e2 = j
                    return
                end if
            end do
        end do

    contains

        !> Whether neighbouring edges i and j lie on one line and point back over each other.
        pure logical function folds_back(i, j)
            integer, intent(in) :: i, j
                !! neighbouring edges

            real(wp) :: a(2), b(2), c(2)

            ! the common vertex b, a the other end of the first, c of the second
            if (j == i + 1) then
                a = p(:, i)
                b = p(:, j)
                c = p(:, modulo(j, n) + 1)
            else
                a = p(:, 2)
                b = p(:, 1)
                c = p(:, n)
            end if
            folds_back = cross(a - b, c - b) == 0.0_wp .and. dot_product(a - b, c - b) > 0.0_wp
        end function folds_back

    end subroutine polygon_crossing

    !> Whether the closed segments a-b and c-d have a point in common.
    pure logical function segments_meet(a, b, c, d)
        real(wp), intent(in) :: a(2), b(2), c(2), d(2)
            !! ends of the segments [m]

        real(wp) :: d1, d2, d3, d4

        d1 = cross(b - a, c - a)
        d2 = cross(b - a, d - a)
        d3 = cross(d - c, a - c)
        d4 = cross(d - c, b - c)
        if (((d1 > 0.0_wp .and. d2 < 0.0_wp) .or. (d1 < 0.0_wp .and. d2 > 0.0_wp)) .and. &
            ((d3 > 0.0_wp .and. d4 < 0.0_wp) .or. (d3 < 0.0_wp .and. d4 > 0.0_wp))) then
            segments_meet = .true.
        else
            ! touching: an end of one on the other
            segments_meet = (d1 == 0.0_wp .and. on_segment(a, b, c)) .or. &
                (d2 == 0.0_wp .and. on_segment(a, b, d)) .or. &
                (d3 == 0.0_wp .and. on_segment(c, d, a)) .or. &
                (d4 == 0.0_wp .and. on_segment(c, d, b))
        end if
    end function segments_meet

    !> Whether q, on the line through a and b, lies between them.
    pure logical function on_segment(a, b, q)
        real(wp), intent(in) :: a(2), b(2), q(2)
            !! the segment and the point [m]

        on_segment = q(1) >= min(a(1), b(1)) .and. q(1) <= max(a(1), b(1)) .and. &
            q(2) >= min(a(2), b(2)) .and. q(2) <= max(a(2), b(2))
    end function on_segment

    !> z component of the cross product of two plane vectors.
    pure real(wp) function cross(u, v)
        real(wp), intent(in) :: u(2), v(2)
            !! the vectors

        cross = u(1)*v(2) - u(2)*v(1)
    end function cross

    !> The walls of the polygon extruded from z = -h to z = h: two triangles per edge,
    !> (coordinate, corner, triangle), for the crossing count of the body filler.
    pure function polygon_walls(p, h) result(triangle)
        real(wp), intent(in) :: p(:, :)
            !! vertices (2, n) [m]
        real(wp), intent(in) :: h
            !! half-height of the extrusion [m]
        real(wp), allocatable :: triangle(:, :, :)
            !! (3, 3, 2 n) the wall triangles [m]

        integer :: i, j, n

        n = size(p, 2)
        allocate (triangle(3, 3, 2*n))
        do i = 1, n
            j = modulo(i, n) + 1
            triangle(:, 1, 2*i - 1) = [p(1, i), p(2, i), -h]
            triangle(:, 2, 2*i - 1) = [p(1, j), p(2, j), -h]
            triangle(:, 3, 2*i - 1) = [p(1, j), p(2, j), h]
            triangle(:, 1, 2*i) = [p(1, i), p(2, i), -h]
            triangle(:, 2, 2*i) = [p(1, j), p(2, j), h]
            triangle(:, 3, 2*i) = [p(1, i), p(2, i), h]
        end do
    end function polygon_walls

end module mpm_polygon
